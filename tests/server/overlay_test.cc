// The robot overlay for any robot and source: a URDF from the config with fixed joint
// positions (no robot state), drawn into a bird's-eye view of the bundled example, turned
// on and off and made more transparent through the API; config mistakes refuse to start.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "tests/server/daemon_process.h"

namespace omniview::testing {
namespace {

std::string urdf() { return std::string(OMNIVIEW_SOURCE_DIR) + "/config/robots/spot/spot_like.urdf"; }

// The example rig's base_link is on the floor: the model's body 0.5 m above it, standing.
std::string overlay_config(const std::string& model_extra = "") {
  return example_config(20,
                        "views:\n"
                        "  - {name: down, type: birdseye, width: 400, height: 400, frame: base_link, height_m: 3,\n"
                        "     hfov_deg: 60, overlay: true, overlay_opacity: 1}\n"
                        "robot_models:\n"
                        "  - source: examples\n"
                        "    urdf: " + urdf() + "\n"
                        "    frame: base_link\n"
                        "    joints: {fl.hy: 0.8, fl.kn: -1.6, fr.hy: 0.8, fr.kn: -1.6, hl.hy: 0.8, hl.kn: -1.6,\n"
                        "             hr.hy: 0.8, hr.kn: -1.6}\n" +
                            model_extra);
}

cv::Mat snapshot_rgb(v1::Omniview::Stub& stub, const std::string& view) {
  v1::SnapshotRequest r;
  r.set_view(view);
  r.set_encoding(v1::RAW);
  v1::Frame f;
  const auto status = stub.GetSnapshot(make_context().get(), r, &f);
  EXPECT_TRUE(status.ok()) << status.error_message();
  if (!status.ok() || f.channels() != 3) return {};
  return cv::Mat(f.height(), f.width(), CV_8UC3, const_cast<char*>(f.data().data())).clone();
}

TEST(Overlay, ConfiguredRobotIsDrawnAndTheApiTurnsItOffAndFades) {
  TempDir dir;
  DaemonProcess daemon(dir, overlay_config());
  auto stub = make_stub(daemon.address());
  const cv::Mat opaque = snapshot_rgb(*stub, "down");
  ASSERT_FALSE(opaque.empty()) << daemon.log();
  // Straight down on base_link: the yellow body (RGB) at the centre.
  const cv::Vec3b centre = opaque.at<cv::Vec3b>(200, 200);
  EXPECT_GT(centre[0], 150);
  EXPECT_GT(centre[1], 120);
  EXPECT_LT(centre[2], 90);

  v1::UpdateViewRequest fade;
  fade.set_name("down");
  fade.mutable_set()->set_overlay_opacity(0.5);
  v1::View view;
  ASSERT_TRUE(stub->UpdateView(make_context().get(), fade, &view).ok());
  EXPECT_DOUBLE_EQ(view.spec().overlay_opacity(), 0.5);
  const cv::Mat half = snapshot_rgb(*stub, "down");
  ASSERT_FALSE(half.empty());
  EXPECT_LT(half.at<cv::Vec3b>(200, 200)[0], centre[0]) << "half as much yellow";

  v1::UpdateViewRequest off;
  off.set_name("down");
  off.mutable_set()->set_overlay(false);
  ASSERT_TRUE(stub->UpdateView(make_context().get(), off, &view).ok());
  EXPECT_FALSE(view.spec().overlay());

  // Only pinhole views can draw the robot.
  v1::CreateViewRequest pano;
  pano.mutable_spec()->set_name("pano");
  pano.mutable_spec()->set_type(v1::EQUIRECTANGULAR);
  pano.mutable_spec()->set_overlay(true);
  const auto refused = stub->CreateView(make_context().get(), pano, &view);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(refused.error_message().find("perspective and birdseye"), std::string::npos) << refused.error_message();
}

v1::JointPositions set_joints(v1::Omniview::Stub& stub, const std::map<std::string, double>& positions,
                              bool clear = false, grpc::Status* status = nullptr, const std::string& token = "") {
  v1::SetJointPositionsRequest r;
  for (const auto& [name, value] : positions) (*r.mutable_positions())[name] = value;
  r.set_clear(clear);
  v1::JointPositions out;
  const grpc::Status s = stub.SetJointPositions(make_context(token).get(), r, &out);
  if (status) {
    *status = s;
  } else {
    EXPECT_TRUE(s.ok()) << s.error_message();
  }
  return out;
}

const v1::Joint* find_joint(const v1::JointPositions& joints, const std::string& name) {
  for (const auto& j : joints.joints()) {
    if (j.name() == name) return &j;
  }
  return nullptr;
}

// The box around the pixels that differ between two frames (empty: none).
cv::Rect changed_area(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat diff, mask;
  cv::absdiff(a, b, diff);
  cv::cvtColor(diff, diff, cv::COLOR_RGB2GRAY);
  cv::threshold(diff, mask, 30, 255, cv::THRESH_BINARY);
  return cv::boundingRect(mask);
}

// A robot whose source reports no joints (an arm's controller, a simulation): its joints
// come through the API, the next frame shows them, and moving one leg changes only the
// picture where that leg is.
TEST(Overlay, JointsSetThroughTheApiMoveOnlyThatLeg) {
  TempDir dir;
  DaemonProcess daemon(dir, overlay_config());
  auto stub = make_stub(daemon.address());
  v1::JointPositions joints;
  ASSERT_TRUE(stub->GetJointPositions(make_context().get(), {}, &joints).ok());
  EXPECT_EQ(joints.source(), "examples");
  ASSERT_EQ(joints.joints_size(), 12);
  EXPECT_EQ(find_joint(joints, "fl.kn")->origin(), v1::Joint::CONFIG);
  EXPECT_DOUBLE_EQ(find_joint(joints, "fl.kn")->position(), -1.6);
  EXPECT_EQ(find_joint(joints, "fl.hx")->origin(), v1::Joint::URDF_ZERO);
  EXPECT_EQ(find_joint(joints, "fl.hx")->unit(), "rad");

  const cv::Mat standing = snapshot_rgb(*stub, "down");
  ASSERT_FALSE(standing.empty()) << daemon.log();
  // Front-left hip out sideways, then the front-right one instead.
  joints = set_joints(*stub, {{"fl.hx", 0.7}});
  EXPECT_EQ(find_joint(joints, "fl.hx")->origin(), v1::Joint::API);
  EXPECT_EQ(find_joint(joints, "fl.kn")->origin(), v1::Joint::CONFIG) << "the others keep their values";
  const cv::Mat left_out = snapshot_rgb(*stub, "down");
  set_joints(*stub, {{"fr.hx", -0.7}}, /*clear=*/true);
  const cv::Mat right_out = snapshot_rgb(*stub, "down");
  ASSERT_FALSE(left_out.empty() || right_out.empty());
  const cv::Rect left = changed_area(standing, left_out), right = changed_area(standing, right_out);
  EXPECT_GT(left.area(), 100) << "moving a leg shows";
  EXPECT_GT(right.area(), 100);
  EXPECT_TRUE((left & right).empty()) << "each leg changes only its own corner: " << left << " vs " << right;

  // Clearing goes back to the config's pose, pixel for pixel.
  joints = set_joints(*stub, {}, /*clear=*/true);
  EXPECT_EQ(find_joint(joints, "fr.hx")->origin(), v1::Joint::URDF_ZERO);
  const cv::Mat again = snapshot_rgb(*stub, "down");
  ASSERT_FALSE(again.empty());
  EXPECT_TRUE(changed_area(standing, again).empty());

  // Mistakes name what to fix; nothing changes.
  grpc::Status status;
  set_joints(*stub, {{"fl.hx", 0.2}, {"elbow", 1}}, false, &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("no movable joint 'elbow'"), std::string::npos) << status.error_message();
  EXPECT_NE(status.error_message().find("fl.hx"), std::string::npos) << "lists the joints it has";
  set_joints(*stub, {{"fl.hx", std::nan("")}}, false, &status);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  set_joints(*stub, {{"fl.kn", 0.5}}, false, &status);  // a knee bent backwards
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("outside its limits [-2.79, -0.25] rad"), std::string::npos)
      << status.error_message();
  ASSERT_TRUE(stub->GetJointPositions(make_context().get(), {}, &joints).ok());
  EXPECT_EQ(find_joint(joints, "fl.hx")->origin(), v1::Joint::URDF_ZERO);
  v1::GetJointPositionsRequest other;
  other.set_source("nobody");
  EXPECT_EQ(stub->GetJointPositions(make_context().get(), other, &joints).error_code(), grpc::StatusCode::NOT_FOUND);
}

TEST(Overlay, JointsNeedAnOperatorAndARobotModel) {
  TempDir dir;
  DaemonProcess daemon(dir, overlay_config("tokens:\n  - {role: viewer, token: viewer-secret-123}\n"
                                           "  - {role: operator, token: operator-secret-456}\n"));
  auto stub = make_stub(daemon.address());
  grpc::Status status;
  set_joints(*stub, {{"fl.hx", 0.2}}, false, &status, "viewer-secret-123");
  EXPECT_EQ(status.error_code(), grpc::StatusCode::PERMISSION_DENIED);
  set_joints(*stub, {{"fl.hx", 0.2}}, false, &status, "operator-secret-456");
  EXPECT_TRUE(status.ok()) << status.error_message();
  v1::JointPositions joints;
  EXPECT_TRUE(stub->GetJointPositions(make_context("viewer-secret-123").get(), {}, &joints).ok());

  // The CLI reads and sets them, degrees too.
  const std::string cli = std::string(OMNIVIEW_CLI) + " joints --server " + daemon.address();
  const std::string op = dir.write("operator.token", "operator-secret-456\n");
  const auto set = run_process(cli + " examples fl.kn=-45deg fr.kn=-1.2 --token-file " + op);
  EXPECT_EQ(set.exit_code, 0) << set.output;
  EXPECT_NE(set.output.find("-0.7854 rad"), std::string::npos) << set.output;
  EXPECT_NE(set.output.find("(-45.0 deg)"), std::string::npos) << set.output;
  EXPECT_NE(set.output.find("api"), std::string::npos) << set.output;
  const auto typo = run_process(cli + " fl.kn=-45dg --token-file " + op);
  EXPECT_EQ(typo.exit_code, 2) << typo.output;
  EXPECT_NE(typo.output.find("fl.kn: expected a number"), std::string::npos) << typo.output;

  // A source without a robot model says where one is configured.
  TempDir plain_dir;
  DaemonProcess plain(plain_dir, example_config(10));
  auto plain_stub = make_stub(plain.address());
  const auto none = plain_stub->GetJointPositions(make_context().get(), {}, &joints);
  EXPECT_EQ(none.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(none.error_message().find("robot_models"), std::string::npos) << none.error_message();
}

// A model frame the source's rig lacks is a config error like any other: --check and a
// start refuse it, naming the entry's line and the frames there are.
TEST(Overlay, AModelFrameTheRigLacksRefusesToStart) {
  TempDir dir;
  std::string config = overlay_config();
  const std::string model_frame = "    frame: base_link\n";
  config.replace(config.find(model_frame), model_frame.size(), "    frame: nosuchframe\n");
  const std::string file = dir.write("bad.yaml", config);
  for (const std::string check : {" --check", ""}) {
    const auto r = run_process(std::string(OMNIVIEWD) + check + " --config " + file);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("bad.yaml:"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("robot_models[0].frame: source 'examples' has no frame 'nosuchframe'"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("base_link"), std::string::npos) << "lists the frames there are: " << r.output;
  }
}

TEST(Overlay, ModelMistakesRefuseToStartNamingTheEntry) {
  TempDir dir;
  const struct {
    std::string config, expected;
  } cases[] = {
      {example_config(10, "robot_models:\n  - {source: examples, urdf: /nonexistent/robot.urdf}\n"),
       "robot_models[0]"},
      {example_config(10, "robot_models:\n  - {source: nobody, urdf: " + urdf() + "}\n"), "no source named 'nobody'"},
      {example_config(10, "robot_models:\n  - {source: examples, urdf: " + urdf() + ", joints: {elbow: 1}}\n"),
       "elbow"},
      {example_config(10, "views:\n  - {name: v, type: birdseye, overlay: true}\n"), "robot_models"},
      {example_config(10, "robot_models:\n  - {source: examples, urdf: " + urdf() + ", joints: {fl.kn: 1}}\n"),
       "outside its limits"},
  };
  for (const auto& c : cases) {
    const std::string config = dir.write("bad.yaml", c.config);
    const auto r = run_process(std::string(OMNIVIEWD) + " --check --config " + config);
    EXPECT_NE(r.exit_code, 0) << c.config;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in:\n" << r.output;
  }
}

}  // namespace
}  // namespace omniview::testing
