// The real `omniview colorize` binary on a small scene: colours, occlusion on and off, the
// printed counts, and clear errors.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <opencv2/core.hpp>

#include "core/cloud/cloud_file.h"
#include "core/io/image_codec.h"

namespace omniview {
namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string output;
};

Result run(const std::string& args) {
  const std::string cmd = std::string(OMNIVIEW_CLI) + " colorize " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

class ColorizeCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("omniview_colorize_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    std::ofstream(dir_ / "rig.yaml") << R"(frame: base_link
cameras:
  - name: front
    camera_model: pinhole
    intrinsics: [100, 100, 79.5, 59.5]
    resolution: [160, 120]
    mount: {xyz: [0, 0, 1], ypr_deg: [0, 0, 0]}
  - name: left
    camera_model: pinhole
    intrinsics: [100, 100, 79.5, 59.5]
    resolution: [160, 120]
    mount: {xyz: [0, 0, 1], ypr_deg: [90, 0, 0]}
)";
    write_image(dir_ / "front.png", cv::Mat(120, 160, CV_8UC3, cv::Scalar(10, 200, 30)));  // BGR green
    write_image(dir_ / "left.png", cv::Mat(120, 160, CV_8UC1, cv::Scalar(90)));
    // A 0.4 m patch 1 m ahead, a point 2 m behind it, one ahead beside it, one on the
    // left, one behind the robot.
    PointCloud cloud;
    cloud.frame = "base_link";
    for (int i = -20; i <= 20; ++i) {
      for (int j = -20; j <= 20; ++j) cloud.points.emplace_back(1.f, 0.01f * i, 1.f + 0.01f * j);
    }
    cloud.points.emplace_back(3.f, 0.f, 1.f);     // hidden behind the patch
    cloud.points.emplace_back(2.f, 0.6f, 1.3f);   // beside it
    cloud.points.emplace_back(0.3f, 2.f, 1.f);    // left camera
    cloud.points.emplace_back(-2.f, 0.f, 1.f);    // nobody
    save_cloud(cloud, (dir_ / "in.pcd").string(), CloudEncoding::kAscii);
    patch_ = 41 * 41;
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string inputs() const {
    return "--rig " + path("rig.yaml") + " --image front=" + path("front.png") + " --image left=" + path("left.png") +
           " --cloud " + path("in.pcd");
  }

  fs::path dir_;
  size_t patch_ = 0;
};

TEST_F(ColorizeCli, ColoursAndCounts) {
  const auto r = run(inputs() + " -o " + path("out.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("1685 points: 1683 coloured, 1 occluded, 0 self-filtered, 1 unseen"), std::string::npos) << r.output;
  const auto out = load_cloud(path("out.ply"));
  ASSERT_EQ(out.size(), patch_ + 4);
  EXPECT_EQ(out.rgb[0], (PointCloud::Rgb{30, 200, 10}));
  EXPECT_EQ(out.flags[patch_], cloud_flags::kOccluded);
  EXPECT_EQ(out.camera[patch_], kNoCamera);
  EXPECT_EQ(out.rgb[patch_ + 1], (PointCloud::Rgb{30, 200, 10}));
  EXPECT_EQ(out.camera[patch_ + 1], 0);
  EXPECT_EQ(out.rgb[patch_ + 2], (PointCloud::Rgb{90, 90, 90}));
  EXPECT_EQ(out.camera[patch_ + 2], 1);
  EXPECT_EQ(out.flags[patch_ + 3], 0);
}

TEST_F(ColorizeCli, WithoutOcclusionTheHiddenPointTakesThePatchColour) {
  const auto r = run(inputs() + " --no-occlusion --fusion blend --out " + path("out.pcd"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("1684 coloured, 0 occluded"), std::string::npos) << r.output;
  const auto out = load_cloud(path("out.pcd"));
  EXPECT_EQ(out.rgb[patch_], (PointCloud::Rgb{30, 200, 10}));
}

TEST_F(ColorizeCli, ACameraWithoutAnImageIsNamed) {
  const auto r = run("--rig " + path("rig.yaml") + " --image front=" + path("front.png") + " --cloud " + path("in.pcd") +
                     " -o " + path("out.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no image for camera left: the points only it sees stay uncoloured (add --image CAM=PATH)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("1682 coloured"), std::string::npos) << "the left camera's point is unseen now: " << r.output;
  EXPECT_EQ(run(inputs() + " -o " + path("all.ply")).output.find("no image for"), std::string::npos);
}

TEST_F(ColorizeCli, ClearErrors) {
  auto r = run(inputs());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;
  r = run(inputs() + " --fusion best -o " + path("o.ply"));
  EXPECT_NE(r.output.find("--fusion must be 'nearest' or 'blend', not 'best'"), std::string::npos) << r.output;
  r = run(inputs() + " --cloud-frame lidar -o " + path("o.ply"));
  EXPECT_NE(r.output.find("the cloud's frame 'lidar' is not a frame of the rig"), std::string::npos) << r.output;
  r = run(inputs() + " -o " + path("o.xyz"));
  EXPECT_NE(r.output.find("give a .ply or .pcd file name"), std::string::npos) << r.output;
  std::ofstream(path("bad.ply")) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n";
  r = run("--rig " + path("rig.yaml") + " --image front=" + path("front.png") + " --cloud " + path("bad.ply") + " -o " +
          path("o.ply"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("bad.ply: element 'vertex': no point field(s) y z"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace omniview
