// The real `omniview render` binary, run as a user would: good renders and clear errors.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <opencv2/imgcodecs.hpp>

namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr
};

Result run(const std::string& args) {
  const std::string cmd = std::string(OMNIVIEW_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

class RenderCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("omniview_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    write("rig.yaml", R"(frame: base_link
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
)");
    write("view.yaml", "name: front\ntype: perspective\nwidth: 64\nheight: 32\nhfov_deg: 60\n");
    cv::imwrite((dir_ / "front.png").string(), cv::Mat(120, 160, CV_8UC3, cv::Scalar(10, 200, 30)));
    cv::imwrite((dir_ / "left.png").string(), cv::Mat(120, 160, CV_8UC1, cv::Scalar(90)));
    cv::imwrite((dir_ / "small.png").string(), cv::Mat(60, 80, CV_8UC3, cv::Scalar(0)));
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string base_args() const {
    return "render --rig " + path("rig.yaml") + " --image front=" + path("front.png") + " --image left=" +
           path("left.png");
  }

  fs::path dir_;
};

TEST_F(RenderCli, RendersAViewFromTheCameraThatSeesIt) {
  const auto r = run(base_args() + " --view " + path("view.yaml") + " --out " + path("out.png"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat out = cv::imread(path("out.png"), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(out.cols, 64);
  ASSERT_EQ(out.rows, 32);
  ASSERT_EQ(out.channels(), 3);
  // A 60 deg view straight ahead lies inside the front camera only: its uniform colour.
  const cv::Vec3b centre = out.at<cv::Vec3b>(16, 32);
  EXPECT_EQ(centre, cv::Vec3b(10, 200, 30));
  EXPECT_NE(r.output.find("coverage 100.0 %"), std::string::npos) << r.output;
}

TEST_F(RenderCli, SeveralViewsGoIntoAFolder) {
  write("views.yaml", "views:\n  - {name: a, type: perspective, width: 32, height: 16}\n"
                      "  - {name: b, type: cylindrical, width: 64, height: 16, azimuth_span_deg: 180}\n");
  const auto r = run(base_args() + " --view " + path("views.yaml") + " --out " + path("views"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "views" / "a.png"));
  EXPECT_TRUE(fs::exists(dir_ / "views" / "b.png"));
  EXPECT_EQ(cv::imread(path("views/b.png")).cols, 64);
}

TEST_F(RenderCli, GreyOutputFromMixedInputs) {
  const auto r = run(base_args() + " --grey --view " + path("view.yaml") + " --out " + path("grey.png"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(cv::imread(path("grey.png"), cv::IMREAD_UNCHANGED).channels(), 1);
}

TEST_F(RenderCli, ListsModelsAndViewTypes) {
  const auto models = run("render --list-models");
  EXPECT_EQ(models.exit_code, 0);
  for (const char* m : {"pinhole", "equidistant", "omni", "ds", "eucm", "fov", "radtan"}) {
    EXPECT_NE(models.output.find(m), std::string::npos) << m;
  }
  const auto types = run("render --list-view-types");
  for (const char* t : {"perspective", "birdseye", "cylindrical", "mercator", "equirectangular", "fisheye"}) {
    EXPECT_NE(types.output.find(t), std::string::npos) << t;
  }
  EXPECT_EQ(run("render --help").exit_code, 0);
  EXPECT_EQ(run("--help").exit_code, 0);
}

TEST_F(RenderCli, WrongImageSizeNamesTheCamera) {
  const auto r = run("render --rig " + path("rig.yaml") + " --image front=" + path("small.png") + " --view " +
                     path("view.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("camera 'front'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("80x60"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("160x120"), std::string::npos) << r.output;
}

TEST_F(RenderCli, MissingImageForANeededCameraSaysWhichFlagToAdd) {
  const auto r = run("render --rig " + path("rig.yaml") + " --view " + path("view.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--image front=PATH"), std::string::npos) << r.output;
}

TEST_F(RenderCli, UsageErrorsAreClear) {
  EXPECT_NE(run("render --veiw x").output.find("unknown option --veiw"), std::string::npos);
  EXPECT_NE(run("render --view " + path("view.yaml")).output.find("missing --rig"), std::string::npos);
  const auto unknown_cam = run("render --rig " + path("rig.yaml") + " --image back=" + path("front.png") +
                               " --view " + path("view.yaml") + " --out " + path("x.png"));
  EXPECT_NE(unknown_cam.output.find("no camera 'back'"), std::string::npos) << unknown_cam.output;
  EXPECT_NE(unknown_cam.output.find("front left"), std::string::npos) << unknown_cam.output;
  EXPECT_EQ(run("frobnicate").exit_code, 2);
}

TEST_F(RenderCli, BadViewFilesNameFileLineAndKey) {
  write("bad.yaml", "name: v\ntype: perspective\nwidth: 64\nheight: 32\nhfov_deg: 180\n");
  auto r = run(base_args() + " --view " + path("bad.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("bad.yaml:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("hfov_deg"), std::string::npos) << r.output;

  write("typo.yaml", "name: v\ntype: perspective\nwidht: 64\n");
  r = run(base_args() + " --view " + path("typo.yaml") + " --out " + path("x.png"));
  EXPECT_NE(r.output.find("typo.yaml:3: widht: unknown key"), std::string::npos) << r.output;

  write("huge.yaml", "name: v\ntype: perspective\nwidth: 20000\nheight: 32\n");
  r = run(base_args() + " --view " + path("huge.yaml") + " --out " + path("x.png"));
  EXPECT_NE(r.output.find("width must be between 1 and 16384"), std::string::npos) << r.output;

  write("zero.yaml", "name: v\ntype: fisheye\nwidth: 0\nheight: 32\n");
  r = run(base_args() + " --view " + path("zero.yaml") + " --out " + path("x.png"));
  EXPECT_NE(r.output.find("width must be between 1 and 16384"), std::string::npos) << r.output;
}

TEST_F(RenderCli, CorruptImageIsAClearError) {
  write("corrupt.jpg", "\xff\xd8\xff\xe0 definitely not a jpeg");
  const auto r = run("render --rig " + path("rig.yaml") + " --image front=" + path("corrupt.jpg") + " --view " +
                     path("view.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("cannot read image"), std::string::npos) << r.output;
}

TEST_F(RenderCli, KalibrCamchainWithRigPose) {
  write("camchain.yaml", R"(cam0:
  camera_model: pinhole
  intrinsics: [100, 100, 79.5, 59.5]
  distortion_model: radtan
  distortion_coeffs: [0, 0, 0, 0]
  resolution: [160, 120]
)");
  // cam0's optical frame looking along base_link's +x: yaw -90, roll -90 turns optical z to x.
  const auto r = run("render --rig " + path("camchain.yaml") + " --rig-pose \"0 0 1 -90 0 -90\" --image cam0=" +
                     path("front.png") + " --view " + path("view.yaml") + " --out " + path("c.png"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(cv::imread(path("c.png")).at<cv::Vec3b>(16, 32), cv::Vec3b(10, 200, 30));
}

}  // namespace
