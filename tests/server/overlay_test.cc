// The robot overlay for any robot and source: a URDF from the config with fixed joint
// positions (no robot state), drawn into a bird's-eye view of the bundled example, turned
// on and off and made more transparent through the API; config mistakes refuse to start.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

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
