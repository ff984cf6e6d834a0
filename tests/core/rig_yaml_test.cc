// Our rig YAML: a good file loads as written, and every mistake names file, line and key.
#include <gtest/gtest.h>

#include <sstream>

#include <opencv2/core.hpp>

#include "core/io/image_codec.h"
#include "core/io/yaml_reader.h"
#include "core/rig/rig.h"
#include "test_support.h"

namespace omniview {
namespace {

using testing::expect_throw_containing;
using testing::kDeg;

class RigYaml : public ::testing::Test {
 protected:
  void expect_error(const std::string& name, const std::string& text, std::initializer_list<std::string> needles) {
    const std::string file = dir_.write(name, text);
    expect_throw_containing<ConfigError>([&] { load_rig_yaml(file); }, needles, name);
  }
  testing::TempDir dir_;
};

// A minimal valid camera entry, indented as an item of `cameras:`.
std::string camera(const std::string& name, const std::string& extra = "") {
  return "  - name: " + name +
         "\n"
         "    camera_model: pinhole\n"
         "    intrinsics: [400, 400, 319.5, 239.5]\n"
         "    resolution: [640, 480]\n"
         "    mount: {xyz: [0, 0, 0]}\n" +
         extra;
}

TEST_F(RigYaml, GoodFileLoadsAsWritten) {
  // The mask sits in a sub-folder next to the file: relative to the file, not to the
  // working directory.
  std::filesystem::create_directories(dir_.path() / "masks");
  cv::Mat mask(480, 640, CV_8UC1, cv::Scalar(255));
  mask(cv::Rect(0, 0, 10, 10)).setTo(0);
  write_image(dir_ / "masks/left.png", mask);
  const Rig rig = load_rig_yaml(dir_.write("rig.yaml", R"(# comment
frame: body
frames:
  - {name: mast, parent: body, T_parent_frame: {xyz: [0.1, 0, 0.5], ypr_deg: [90, 0, 0]}}
  - name: head
    parent: mast
    T_parent_frame: {xyz: [0, 0, 0.2]}
cameras:
  - name: left
    camera_model: omni
    intrinsics: [0.9, 300, 300, 320, 240]
    distortion_model: radtan
    distortion_coeffs: [-0.2, 0.05, 0, 0, 0.001]
    resolution: [640, 480]
    parent: head
    mount: {xyz: [0, 0, 0.1], ypr_deg: [0, 10, 0]}
    mask: masks/left.png
    fov_deg: 190
  - name: right
    camera_model: eucm
    intrinsics: [0.6, 1.1, 300, 300, 320, 240]
    resolution: [640, 480]
    T_parent_cam: {xyz: [0, -0.1, 0], quat_xyzw: [0, 0, 0, 1]}
)"));
  ASSERT_EQ(rig.cameras().size(), 2u);
  EXPECT_EQ(rig.default_frame(), "body");
  const Camera& left = rig.cameras()[0];
  EXPECT_EQ(left.name, "left");
  EXPECT_EQ(left.width, 640);
  EXPECT_EQ(left.height, 480);
  EXPECT_EQ(left.parent_frame, "head");
  EXPECT_EQ(left.fov_deg, 190);
  ASSERT_EQ(left.mask.size(), cv::Size(640, 480));
  EXPECT_EQ(left.mask.at<uint8_t>(5, 5), 0);
  EXPECT_EQ(left.mask.at<uint8_t>(100, 100), 255);
  ASSERT_TRUE(std::holds_alternative<OmniRadtan>(left.model));
  EXPECT_EQ(std::get<OmniRadtan>(left.model).distortion().k3, 0.001);
  // mount is posed like a view: the optical axis along head's x pitched 10 deg down; head
  // hangs from the mast, yawed 90 deg in body, so in body the axis points along +y and down.
  const Pose T_body_left = rig.camera_pose("body", 0);
  EXPECT_TRUE(
      (T_body_left.linear() * Vec3::UnitZ()).isApprox(Vec3(0, std::cos(10 * kDeg), -std::sin(10 * kDeg)), 1e-12));
  // Optical x (image right) is the view's -y: in body, +x after the 90 deg yaw.
  EXPECT_TRUE((T_body_left.linear() * Vec3::UnitX()).isApprox(Vec3(1, 0, 0), 1e-12));
  EXPECT_TRUE(T_body_left.translation().isApprox(Vec3(0.1, 0, 0.8), 1e-12));
  // T_parent_cam is the optical frame itself; no parent means the rig's frame.
  EXPECT_EQ(rig.cameras()[1].parent_frame, "body");
  EXPECT_TRUE(rig.camera_pose("body", 1).isApprox(make_pose(Vec3(0, -0.1, 0), 0, 0, 0), 1e-15));
  EXPECT_EQ(rig.cameras()[1].mask.empty(), true);
  EXPECT_EQ(rig.cameras()[1].fov_deg, 0) << "no fov_deg: the model's own limit";
  ASSERT_NE(rig.find("right"), nullptr);
  EXPECT_EQ(rig.find("nobody"), nullptr);
  EXPECT_TRUE(rig.frames().has_frame("mast"));
}

TEST_F(RigYaml, MountAndTParentCamDescribeTheSamePose) {
  // mount {ypr} == T_parent_cam with R = R(ypr) * R_view_optical.
  const Pose T = make_pose(Vec3(0.2, -0.3, 1.0), 30 * kDeg, 20 * kDeg, -5 * kDeg);
  Pose T_optical = T;
  T_optical.linear() = T.linear() * R_view_optical();
  std::ostringstream matrix;
  matrix.precision(17);
  for (int r = 0; r < 4; ++r) {
    matrix << "      - [" << T_optical.matrix()(r, 0) << ", " << T_optical.matrix()(r, 1) << ", "
           << T_optical.matrix()(r, 2) << ", " << T_optical.matrix()(r, 3) << "]\n";
  }
  const Rig rig =
      load_rig_yaml(dir_.write("rig.yaml",
                               "cameras:\n"
                               "  - name: a\n    camera_model: pinhole\n    intrinsics: [1, 1, 0, 0]\n"
                               "    resolution: [4, 4]\n    mount: {xyz: [0.2, -0.3, 1.0], ypr_deg: [30, 20, -5]}\n"
                               "  - name: b\n    camera_model: pinhole\n    intrinsics: [1, 1, 0, 0]\n"
                               "    resolution: [4, 4]\n    T_parent_cam:\n" +
                                   matrix.str()));
  EXPECT_TRUE(rig.camera_pose("base_link", 0).isApprox(rig.camera_pose("base_link", 1), 1e-12));
  EXPECT_EQ(rig.default_frame(), "base_link") << "the default when the file names no frame";
}

TEST_F(RigYaml, UnknownKeyNamesFileLineAndKey) {
  expect_error("typo.yaml", "cameras:\n  - name: a\n    camera_modle: pinhole\n",
               {"typo.yaml:3: cameras[0].camera_modle: unknown key", "camera_model"});
  expect_error("top.yaml", "camera:\n" + camera("a"), {"top.yaml:1: camera: unknown key"});
  expect_error("mount.yaml", "cameras:\n" + camera("a") + "    mount_typo: 1\n", {"mount.yaml:7", "mount_typo"});
}

TEST_F(RigYaml, MissingOrWrongIntrinsics) {
  expect_error("missing.yaml", "cameras:\n  - name: a\n    camera_model: pinhole\n    resolution: [4, 4]\n",
               {"missing.yaml:2: cameras[0] (a): missing required key 'intrinsics'"});
  // A wrong count points at the intrinsics' own line.
  expect_error("count.yaml",
               "cameras:\n  - name: a\n    camera_model: ds\n    intrinsics: [1, 2]\n"
               "    resolution: [4, 4]\n    mount: {}\n",
               {"count.yaml:4: cameras[0] (a): intrinsics needs 6 values", "got 2"});
  expect_error(
      "coeffs.yaml",
      "cameras:\n  - name: a\n    camera_model: pinhole\n    intrinsics: [1, 1, 0, 0]\n"
      "    distortion_model: radtan\n    distortion_coeffs: [0.1, 0.2]\n    resolution: [4, 4]\n    mount: {}\n",
      {"coeffs.yaml:6: cameras[0] (a): distortion_coeffs needs 4 or 5 values"});
  expect_error("focal.yaml",
               "cameras:\n  - name: a\n    camera_model: pinhole\n    intrinsics: [0, 1, 0, 0]\n"
               "    resolution: [4, 4]\n    mount: {}\n",
               {"focal.yaml:4: cameras[0] (a): intrinsics: focal lengths"});
  expect_error("unknown.yaml",
               "cameras:\n  - name: a\n    camera_model: scaramuzza\n    intrinsics: [1]\n"
               "    resolution: [4, 4]\n    mount: {}\n",
               {"unknown.yaml:3: cameras[0] (a): unknown camera_model 'scaramuzza'"});
  expect_error("nan.yaml",
               "cameras:\n  - name: a\n    camera_model: pinhole\n    intrinsics: [1, .nan, 0, 0]\n"
               "    resolution: [4, 4]\n    mount: {}\n",
               {"nan.yaml:4: cameras[0] (a).intrinsics[1]: must be finite"});
  expect_error("res.yaml",
               "cameras:\n  - name: a\n    camera_model: pinhole\n    intrinsics: [1, 1, 0, 0]\n"
               "    resolution: [640.5, 480]\n    mount: {}\n",
               {"res.yaml:5: cameras[0] (a).resolution"});
}

TEST_F(RigYaml, MaskErrorsPointAtTheMask) {
  write_image(dir_ / "small.png", cv::Mat(2, 2, CV_8UC1, cv::Scalar(255)));
  expect_error("mask.yaml", "cameras:\n" + camera("a", "    mask: small.png\n"),
               {"mask.yaml:7: cameras[0] (a).mask", "2x2", "640x480"});
  expect_error("nomask.yaml", "cameras:\n" + camera("a", "    mask: none.png\n"),
               {"nomask.yaml:7: cameras[0] (a).mask: cannot read mask image", "none.png"});
  // Not an image at all.
  dir_.write("text.png", "not a png");
  expect_error("garbage.yaml", "cameras:\n" + camera("a", "    mask: text.png\n"),
               {"garbage.yaml:7", "cannot read mask image"});
}

TEST_F(RigYaml, NonRigidTransform) {
  expect_error("rigid.yaml",
               "cameras:\n  - name: a\n    camera_model: pinhole\n    intrinsics: [1, 1, 0, 0]\n"
               "    resolution: [4, 4]\n    T_parent_cam:\n      - [2, 0, 0, 0]\n"
               "      - [0, 1, 0, 0]\n      - [0, 0, 1, 0]\n      - [0, 0, 0, 1]\n",
               {"rigid.yaml:7", "cameras[0] (a).T_parent_cam", "not a rotation"});
  expect_error("frame.yaml",
               "frames:\n  - {name: m, parent: base_link, T_parent_frame: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], "
               "[0, 0, 1, 1]]}\ncameras:\n" +
                   camera("a"),
               {"frame.yaml:2", "frames[0].T_parent_frame", "last row"});
  expect_error("both.yaml", "cameras:\n" + camera("a", "    T_parent_cam: {xyz: [0, 0, 0]}\n"),
               {"both.yaml:2", "either T_parent_cam or mount"});
  expect_error(
      "none.yaml",
      "cameras:\n  - name: a\n    camera_model: pinhole\n    intrinsics: [1, 1, 0, 0]\n    resolution: [4, 4]\n",
      {"none.yaml:2", "missing the camera's pose"});
}

TEST_F(RigYaml, DuplicateNames) {
  expect_error("dup.yaml", "cameras:\n" + camera("a") + camera("a"), {"dup.yaml:7: cameras[1] (a)", "defined twice"});
  // A camera must not silently re-hang a declared frame (and the frames below it).
  expect_error(
      "clash.yaml",
      "frames:\n  - {name: mast, parent: base_link, T_parent_frame: {xyz: [0, 0, 1]}}\ncameras:\n" + camera("mast"),
      {"clash.yaml:4: cameras[0] (mast)", "already has a frame of that name"});
  expect_error("frames.yaml",
               "frames:\n  - {name: mast, parent: base_link, T_parent_frame: {}}\n"
               "  - {name: mast, parent: base_link, T_parent_frame: {xyz: [1, 0, 0]}}\ncameras:\n" +
                   camera("a"),
               {"frames.yaml:3: frames[1]", "'mast' is defined twice"});
  // A repeated key inside one camera: yaml-cpp would quietly use the first.
  expect_error("key.yaml", "cameras:\n" + camera("a", "    resolution: [320, 240]\n"),
               {"key.yaml:7: cameras[0].resolution: key given twice (first on line 5)"});
}

TEST_F(RigYaml, FramesMayReferToLaterFramesAndCamerasToFramesButNotCycles) {
  // A camera may hang from a frame that another camera named only as a parent so far.
  const Rig rig = load_rig_yaml(dir_.write("ok.yaml", "cameras:\n" + camera("a", "    parent: b\n") + camera("b")));
  EXPECT_TRUE(rig.frames().try_lookup("base_link", "a"));
  expect_error("cycle.yaml",
               "frames:\n  - {name: p, parent: q, T_parent_frame: {}}\n  - {name: q, parent: p, T_parent_frame: {}}\n"
               "cameras:\n" +
                   camera("a"),
               {"cycle.yaml:3: frames[1]", "cycle"});
}

TEST_F(RigYaml, UnknownParentFramesAreReportedAtLoadWithTheKnownFrames) {
  // Not only once a view is rendered: at the parent's line, listing what is known.
  expect_error("parent.yaml",
               "frames:\n  - {name: mast, parent: base_link, T_parent_frame: {}}\ncameras:\n" + camera("a") +
                   camera("b", "    parent: mats\n"),
               {"parent.yaml:14: cameras[1] (b).parent: 'mats' is not a known frame",
                "known frames: base_link, a, mast", "define it under 'frames:'"});
  // A frame hanging from an unknown one is reported at that frame, naming the unknown root.
  expect_error("chain.yaml",
               "frames:\n  - {name: head, parent: mast, T_parent_frame: {}}\n"
               "  - {name: mast, parent: tower, T_parent_frame: {}}\ncameras:\n" +
                   camera("a", "    parent: head\n"),
               {"chain.yaml:2: frames[0].parent: 'mast' hangs from 'tower', which is not a known frame",
                "known frames: base_link"});
  // The rig's own frame counts even when no camera names it as parent explicitly.
  expect_error("frame.yaml", "frame: body\ncameras:\n" + camera("a", "    parent: base_link\n"),
               {"frame.yaml:8: cameras[0] (a).parent: 'base_link' is not a known frame", "known frames: body"});
}

TEST_F(RigYaml, MissingAndUndecodableMasksDiffer) {
  expect_error("nomask.yaml", "cameras:\n" + camera("a", "    mask: none.png\n"), {"none.png': no such file"});
  dir_.write("text.png", "not a png");
  expect_error("garbage.yaml", "cameras:\n" + camera("a", "    mask: text.png\n"),
               {"text.png': not a decodable image"});
}

TEST_F(RigYaml, SyntaxErrorsAndMissingFiles) {
  expect_error("syntax.yaml", "cameras: [\n  - name: a\n", {"syntax.yaml:", "YAML syntax error"});
  expect_error("tabs.yaml", "cameras:\n  - name: a\n     camera_model: x\n", {"tabs.yaml:3", "YAML syntax error"});
  expect_throw_containing<ConfigError>([&] { load_rig_yaml(dir_ / "absent.yaml"); },
                                       {"absent.yaml", "cannot open file"});
  expect_error("empty.yaml", "", {"empty.yaml", "expected a rig"});
  expect_error("list.yaml", "- a\n- b\n", {"list.yaml:1", "expected a rig"});
  expect_error("nocams.yaml", "frame: body\n", {"nocams.yaml:1", "missing required key 'cameras'"});
  expect_error("zerocams.yaml", "cameras: []\n", {"zerocams.yaml:1: cameras", "non-empty list"});
}

}  // namespace
}  // namespace omniview
