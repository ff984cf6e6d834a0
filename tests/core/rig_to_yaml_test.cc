// rig_to_yaml / save_rig_yaml: what they write, parse_rig_yaml reads back exactly.
#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "core/io/yaml_reader.h"
#include "core/rig/rig.h"

namespace omniview {
namespace {

Rig sample_rig() {
  Rig rig("base_link");
  rig.add_frame("mast", "base_link", make_pose(Vec3(0.2, 0.0, 0.5), 0.1, 0.2, 0.3));
  Camera a;
  a.name = "front";
  a.width = 64;
  a.height = 48;
  a.model = make_camera_model(
      {"pinhole", "equidistant", {30.1, 30.2, 31.5, 23.5}, {0.02, -0.004, 0.0005, -0.0001}}, "a");
  a.fov_deg = 210;
  a.parent_frame = "mast";
  a.T_parent_cam = make_pose(Vec3(0.01, 0.02, 1.0), 1.0 / 3, -0.7, 3.0);
  a.mask = cv::Mat(48, 64, CV_8UC1, cv::Scalar(255));
  a.mask(cv::Rect(0, 0, 10, 10)).setTo(0);
  rig.add_camera(a);
  Camera b;
  b.name = "side cam";  // a name with a space survives the round trip
  b.width = 32;
  b.height = 32;
  b.model = make_camera_model({"ds", "none", {-0.2, 0.6, 20, 21, 15.5, 15.5}, {}}, "b");
  b.T_parent_cam = make_pose(Vec3(-0.3, 0, 0), 2.0, 0, 0);
  rig.add_camera(b);
  return rig;
}

void expect_same(const Rig& want, const Rig& got, bool masks) {
  EXPECT_EQ(want.default_frame(), got.default_frame());
  EXPECT_EQ(want.frames().frames(), got.frames().frames());
  ASSERT_EQ(want.cameras().size(), got.cameras().size());
  for (size_t i = 0; i < want.cameras().size(); ++i) {
    const Camera& w = want.cameras()[i];
    const Camera& g = got.cameras()[i];
    EXPECT_EQ(w.name, g.name);
    EXPECT_EQ(w.width, g.width);
    EXPECT_EQ(w.height, g.height);
    EXPECT_EQ(w.fov_deg, g.fov_deg);
    EXPECT_EQ(w.parent_frame, g.parent_frame);
    const ModelSpec ws = describe(w.model), gs = describe(g.model);
    EXPECT_EQ(ws.camera_model, gs.camera_model);
    EXPECT_EQ(ws.distortion_model, gs.distortion_model);
    EXPECT_EQ(ws.intrinsics, gs.intrinsics);
    EXPECT_EQ(ws.distortion, gs.distortion);
    EXPECT_TRUE(w.T_parent_cam.matrix().isApprox(g.T_parent_cam.matrix(), 1e-12)) << w.name;
    if (masks) {
      ASSERT_EQ(w.mask.empty(), g.mask.empty()) << w.name;
      if (!w.mask.empty()) {
        EXPECT_EQ(cv::norm(w.mask, g.mask, cv::NORM_INF), 0);
      }
    } else {
      EXPECT_TRUE(g.mask.empty());
    }
  }
  EXPECT_TRUE(want.frames().lookup("base_link", "mast").matrix().isApprox(
      got.frames().lookup("base_link", "mast").matrix(), 1e-12));
}

TEST(RigToYaml, RoundTripsThroughParse) {
  const Rig rig = sample_rig();
  const std::string text = rig_to_yaml(rig);
  EXPECT_EQ(text.find("mask"), std::string::npos) << "masks are only written by save_rig_yaml";
  const Rig back = parse_rig_yaml(YamlReader::from_string(text, "rig.yaml"), ".");
  expect_same(rig, back, false);
}

TEST(RigToYaml, SaveWritesMasksBeside) {
  const auto dir = std::filesystem::temp_directory_path() / ("rig_to_yaml_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const Rig rig = sample_rig();
  save_rig_yaml(rig, (dir / "rig.yaml").string());
  EXPECT_TRUE(std::filesystem::exists(dir / "front_mask.png"));
  EXPECT_FALSE(std::filesystem::exists(dir / "side cam_mask.png"));
  expect_same(rig, load_rig_yaml((dir / "rig.yaml").string()), true);
  std::filesystem::remove_all(dir);
}

TEST(RigToYaml, WritesLiveExtrinsicsFromTheFrameGraph) {
  Rig rig = sample_rig();
  const Pose moved = make_pose(Vec3(1, 2, 3), 0.5, 0, 0);
  rig.frames().set_parent("front", "base_link", moved);
  const Rig back = parse_rig_yaml(YamlReader::from_string(rig_to_yaml(rig), "rig.yaml"), ".");
  EXPECT_EQ(back.cameras()[0].parent_frame, "base_link");
  EXPECT_TRUE(back.cameras()[0].T_parent_cam.matrix().isApprox(moved.matrix(), 1e-12));
}

TEST(RigToYaml, BundledExampleRoundTrips) {
  // Not __FILE__: ccache makes it relative to the source tree (CMakeLists.txt).
  const auto example = std::filesystem::path(OMNIVIEW_SOURCE_DIR) / "config/examples/dual_fisheye/rig.yaml";
  const Rig rig = load_rig_yaml(example.string());
  const Rig back = parse_rig_yaml(YamlReader::from_string(rig_to_yaml(rig), "rig.yaml"), ".");
  ASSERT_EQ(back.cameras().size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_TRUE(rig.cameras()[i].T_parent_cam.matrix().isApprox(back.cameras()[i].T_parent_cam.matrix(), 1e-12));
    EXPECT_EQ(describe(rig.cameras()[i].model).intrinsics, describe(back.cameras()[i].model).intrinsics);
  }
}

}  // namespace
}  // namespace omniview
