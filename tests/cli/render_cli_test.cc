// The real `omniview render` binary, run as a user would: good renders and clear errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <opencv2/core.hpp>

#include "core/io/image_codec.h"

namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr
};

Result run_program(const std::string& program, const std::string& args) {
  const std::string cmd = program + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

Result run(const std::string& args) { return run_program(OMNIVIEW_CLI, args); }

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
    omniview::write_image(dir_ / "front.png", cv::Mat(120, 160, CV_8UC3, cv::Scalar(10, 200, 30)));
    omniview::write_image(dir_ / "left.png", cv::Mat(120, 160, CV_8UC1, cv::Scalar(90)));
    omniview::write_image(dir_ / "small.png", cv::Mat(60, 80, CV_8UC3, cv::Scalar(0)));
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
  const cv::Mat out = omniview::read_image(path("out.png"));
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
  EXPECT_EQ(omniview::read_image(path("views/b.png"), omniview::ImageColour::kBgr).cols, 64);
}

TEST_F(RenderCli, GreyOutputFromMixedInputs) {
  const auto r = run(base_args() + " --grey --view " + path("view.yaml") + " --out " + path("grey.png"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(omniview::read_image(path("grey.png")).channels(), 1);
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

TEST_F(RenderCli, WrongImageSizeNamesTheCameraTheFileAndBothSizes) {
  const auto r = run("render --rig " + path("rig.yaml") + " --image front=" + path("small.png") + " --view " +
                     path("view.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("camera 'front'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(path("small.png")), std::string::npos) << r.output;
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

TEST_F(RenderCli, MissingAndCorruptImagesAreDifferentClearErrors) {
  write("corrupt.jpg", "\xff\xd8\xff\xe0 definitely not a jpeg");
  auto r = run("render --rig " + path("rig.yaml") + " --image front=" + path("corrupt.jpg") + " --view " +
               path("view.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("camera 'front': '" + path("corrupt.jpg") + "' is not a decodable image"), std::string::npos)
      << r.output;
  r = run("render --rig " + path("rig.yaml") + " --image front=" + path("absent.png") + " --view " + path("view.yaml") +
          " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("camera 'front': image file '" + path("absent.png") + "' does not exist"), std::string::npos)
      << r.output;
  // Only our message: no OpenCV log lines.
  EXPECT_EQ(r.output.find("WARN"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
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
  // The same rotation as a quaternion qx qy qz qw; both are the help's example.
  for (const char* pose : {"0 0 1 -90 0 -90", "0 0 1 -0.5 0.5 -0.5 0.5"}) {
    fs::remove(dir_ / "c.png");
    const auto r = run("render --rig " + path("camchain.yaml") + " --rig-pose \"" + pose + "\" --image cam0=" +
                       path("front.png") + " --view " + path("view.yaml") + " --out " + path("c.png"));
    ASSERT_EQ(r.exit_code, 0) << pose << "\n" << r.output;
    const cv::Mat c = omniview::read_image(path("c.png"), omniview::ImageColour::kBgr);
    EXPECT_EQ(c.at<cv::Vec3b>(16, 32), cv::Vec3b(10, 200, 30)) << pose;
    EXPECT_NE(r.output.find("coverage 100.0 %"), std::string::npos) << pose << "\n" << r.output;
  }
  const std::string help = run("render --help").output;
  EXPECT_NE(help.find("cam0's optical frame (z along the optical"), std::string::npos) << help;
  EXPECT_NE(help.find("--rig-pose \"0 0 1 -90 0 -90\""), std::string::npos) << help;
}

TEST_F(RenderCli, RigPoseTakesSixOrSevenNumbers) {
  write("camchain.yaml", "cam0:\n  camera_model: pinhole\n  intrinsics: [100, 100, 79.5, 59.5]\n"
                         "  resolution: [160, 120]\n");
  const auto with_pose = [&](const std::string& pose) {
    return run("render --rig " + path("camchain.yaml") + " --rig-pose \"" + pose + "\" --image cam0=" +
               path("front.png") + " --view " + path("view.yaml") + " --out " + path("c.png"));
  };
  for (const char* wrong : {"0 0 1 -90 0", "0 0 1 -90 0 -90 5 6"}) {
    const auto r = with_pose(wrong);
    EXPECT_EQ(r.exit_code, 2) << wrong;
    EXPECT_NE(r.output.find("6 numbers \"x y z yaw pitch roll\""), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("7 numbers \"x y z qx qy qz qw\""), std::string::npos) << r.output;
  }
  EXPECT_NE(with_pose("1").output.find("got 1 number:"), std::string::npos);
  // 7 numbers are a quaternion, not yaw pitch roll with one to spare.
  EXPECT_NE(with_pose("0 0 1 -90 0 -90 0").output.find("must have unit length"), std::string::npos);
  EXPECT_NE(with_pose("0 0 one 0 0 0").output.find("'one' is not a number"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "c.png"));
}

TEST_F(RenderCli, RigFrameAndPoseApplyOnlyToCamchains) {
  for (const std::string option : {"--rig-pose \"0 0 1 0 0 0\"", "--rig-frame body"}) {
    const auto r = run(base_args() + " " + option + " --view " + path("view.yaml") + " --out " + path("x.png"));
    EXPECT_EQ(r.exit_code, 2) << option;
    EXPECT_NE(r.output.find("applies only to kalibr camchains"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "x.png"));
  }
}

TEST_F(RenderCli, ViewFramesUnknownToACamchainHintAtRigFrame) {
  write("camchain.yaml", "cam0:\n  camera_model: pinhole\n  intrinsics: [100, 100, 79.5, 59.5]\n"
                         "  resolution: [160, 120]\n  rostopic: /cam0/image_raw\n  timeshift_cam_imu: 0.001\n");
  write("body.yaml", "name: v\ntype: perspective\nframe: body\n");
  const auto r = run("render --rig " + path("camchain.yaml") + " --image cam0=" + path("front.png") + " --view " +
                     path("body.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("frame 'body' is not a frame of the rig (known frames: base_link, cam0)"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("give --rig-frame body"), std::string::npos) << r.output;
  // With it, the same view renders.
  EXPECT_EQ(run("render --rig " + path("camchain.yaml") + " --rig-frame body --image cam0=" + path("front.png") +
                " --view " + path("body.yaml") + " --out " + path("x.png"))
                .exit_code,
            0);
}

TEST_F(RenderCli, UnknownCameraParentIsReportedAtRigLoad) {
  write("bad_rig.yaml", "cameras:\n  - name: front\n    camera_model: pinhole\n    intrinsics: [100, 100, 79.5, 59.5]\n"
                        "    resolution: [160, 120]\n    parent: mast\n    mount: {}\n");
  const auto r = run("render --rig " + path("bad_rig.yaml") + " --image front=" + path("front.png") + " --view " +
                     path("view.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("bad_rig.yaml:6: cameras[0] (front).parent: 'mast' is not a known frame (known frames: "
                          "base_link)"),
            std::string::npos)
      << r.output;
}

TEST_F(RenderCli, SeveralViewsNeedAFolder) {
  write("views.yaml", "views:\n  - {name: a, type: perspective, width: 32, height: 16}\n"
                      "  - {name: b, type: perspective, width: 32, height: 16}\n");
  const auto r = run(base_args() + " --view " + path("views.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("with 2 views --out must be a folder"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
  // A folder name with a dot is fine written with a trailing slash, and so is a lone view into a folder.
  ASSERT_EQ(run(base_args() + " --view " + path("views.yaml") + " --out " + path("renders.v2/")).exit_code, 0);
  EXPECT_TRUE(fs::exists(dir_ / "renders.v2" / "b.png"));
  ASSERT_EQ(run(base_args() + " --view " + path("view.yaml") + " --out " + path("one/")).exit_code, 0);
  EXPECT_TRUE(fs::exists(dir_ / "one" / "front.png"));
}

TEST_F(RenderCli, OutputFormatIsCheckedBeforeRendering) {
  auto r = run(base_args() + " --view " + path("view.yaml") + " --out " + path("x.gif"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("cannot write .gif images; supported: .png .jpg"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("coverage"), std::string::npos) << "checked before rendering:\n" << r.output;
  r = run(base_args() + " --view " + path("view.yaml") + " --out " + path("noext"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("give the output image a file extension"), std::string::npos) << r.output;
  // Upper case is the same format.
  EXPECT_EQ(run(base_args() + " --view " + path("view.yaml") + " --out " + path("x.JPG")).exit_code, 0);
}

TEST_F(RenderCli, RepeatedViewNamesNameBothSources) {
  write("other.yaml", "name: front\ntype: fisheye\nwidth: 32\nheight: 32\n");
  const auto r = run(base_args() + " --view " + path("view.yaml") + " --view " + path("other.yaml") + " --out " +
                     path("out/"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("view name 'front' is used twice: in " + path("view.yaml") + " and in " + path("other.yaml")),
            std::string::npos)
      << r.output;
  write("two.yaml", "views:\n  - {name: front, type: perspective}\n  - {name: front, type: fisheye}\n");
  EXPECT_NE(run(base_args() + " --view " + path("two.yaml") + " --out " + path("out/"))
                .output.find("two.yaml:3: views[1].name: view name 'front' is already used by views[0] on line 2"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(RenderCli, AllViewsAreCheckedBeforeAnyIsWritten) {
  // The third view looks left, and no --image gives the left camera; the frame of the
  // fourth is unknown. Neither may leave the first two written.
  write("views.yaml", "views:\n  - {name: a, type: perspective, width: 32, height: 16, hfov_deg: 30}\n"
                      "  - {name: b, type: perspective, width: 32, height: 16, hfov_deg: 30}\n"
                      "  - {name: c, type: perspective, width: 32, height: 16, hfov_deg: 30, pose: {ypr_deg: [90, 0, 0]}}\n");
  auto r = run("render --rig " + path("rig.yaml") + " --image front=" + path("front.png") + " --view " +
               path("views.yaml") + " --out " + path("out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("view 'c' needs camera 'left', which has no image: add --image left=PATH"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "a.png"));
  write("frame.yaml", "views:\n  - {name: a, type: perspective}\n  - {name: b, type: perspective, frame: nowhere}\n");
  r = run(base_args() + " --view " + path("frame.yaml") + " --out " + path("out"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("view 'b' (" + path("frame.yaml") + " views[1]): frame 'nowhere' is not a frame of the rig"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "a.png"));
}

TEST_F(RenderCli, ArgumentErrorsAndHelp) {
  auto r = run("render --frobnicate");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown option --frobnicate"), std::string::npos) << r.output;
  // --help and -h win wherever they appear, even after a mistake or where a value belongs.
  for (const char* args : {"render --frobnicate --help", "render --rig -h", "render --rig a --rig b --help"}) {
    r = run(args);
    EXPECT_EQ(r.exit_code, 0) << args;
    EXPECT_NE(r.output.find("usage: omniview render"), std::string::npos) << args << "\n" << r.output;
  }
  r = run(base_args() + " --rig " + path("rig.yaml") + " --view " + path("view.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--rig given twice"), std::string::npos) << r.output;
  r = run(base_args() + " --grey --colour --view " + path("view.yaml") + " --out " + path("x.png"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--grey and --colour contradict each other"), std::string::npos) << r.output;
  r = run(base_args() + " --image front=" + path("front.png") + " --view " + path("view.yaml") + " --out " +
          path("x.png"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--image front given twice"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

TEST_F(RenderCli, Version) {
  const auto r = run("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.output, std::string("omniview ") + OMNIVIEW_VERSION + "\n");
}

TEST_F(RenderCli, MakeExamplesHelp) {
  for (const char* flag : {"--help", "-h"}) {
    const auto r = run_program(OMNIVIEW_MAKE_EXAMPLES, flag);
    EXPECT_EQ(r.exit_code, 0) << flag;
    EXPECT_NE(r.output.find("usage: omniview_make_examples"), std::string::npos) << r.output;
  }
  EXPECT_EQ(run_program(OMNIVIEW_MAKE_EXAMPLES, "--frobnicate").exit_code, 2);
}

}  // namespace

// ---- depth: measured with --cloud ----

namespace {

// An ascii PLY of a wall x = 3 m in front of the rig (y -2..2, z 0..2), with `extra` lines
// appended as more vertices (the header counts them).
std::string wall_ply(const std::vector<std::string>& extra = {}) {
  std::string body;
  size_t n = 0;
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j <= 20; ++j, ++n) body += "3 " + std::to_string(-2 + 0.1 * i) + " " + std::to_string(0.1 * j) + "\n";
  }
  for (const auto& e : extra) body += e + "\n", ++n;
  return "ply\nformat ascii 1.0\nelement vertex " + std::to_string(n) +
         "\nproperty float x\nproperty float y\nproperty float z\nend_header\n" + body;
}

}  // namespace

TEST_F(RenderCli, AMeasuredDepthViewStandsOnTheCloudAndSaysHowMuch) {
  write("measured.yaml", "name: front\ntype: perspective\nwidth: 64\nheight: 32\nhfov_deg: 60\ndepth: measured\n"
                         "pose: {xyz: [0, 0, 1]}\n");
  write("wall.ply", wall_ply({"nan nan nan", "inf 0 0"}));
  const auto r = run(base_args() + " --view " + path("measured.yaml") + " --cloud " + path("wall.ply") + " --out " +
                     path("out.png"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("% on measured depth"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("2 NaN/inf skipped"), std::string::npos) << r.output;
  const cv::Mat out = omniview::read_image(path("out.png"));
  ASSERT_EQ(out.cols, 64);
  EXPECT_EQ(out.at<cv::Vec3b>(16, 32), cv::Vec3b(10, 200, 30));  // the front camera's colour
}

TEST_F(RenderCli, BadCloudsAndMissingCloudsAreClearErrors) {
  write("measured.yaml", "name: m\ntype: perspective\nwidth: 64\nheight: 32\nhfov_deg: 60\ndepth: measured\n");
  const std::string measured = base_args() + " --view " + path("measured.yaml") + " --out " + path("out.png");
  auto r = run(measured);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("has depth: measured: give the points it stands on with --cloud FILE"), std::string::npos)
      << r.output;

  write("broken.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n");
  r = run(measured + " --cloud " + path("broken.ply"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("broken.ply"), std::string::npos) << r.output;

  write("empty.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                     "end_header\n");
  r = run(measured + " --cloud " + path("empty.ply"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("empty.ply: the cloud has no points"), std::string::npos) << r.output;

  // More points than render takes (20 M): refused by the header's count, before a body
  // (here a short one) would be parsed.
  write("huge.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 21000000\nproperty float x\n"
                    "property float y\nproperty float z\nend_header\n0123456789ab");
  r = run(measured + " --cloud " + path("huge.ply"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--cloud " + path("huge.ply") +
                          ": its header declares 21000000 points, more than the limit of 20000000"),
            std::string::npos)
      << r.output;

  write("wall.ply", wall_ply());
  r = run(measured + " --cloud " + path("wall.ply") + " --cloud-frame lidar");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("wall.ply: its frame 'lidar' (--cloud-frame) is not a frame of the rig"), std::string::npos)
      << r.output;

  r = run(measured + " --cloud " + path("missing.ply"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("missing.ply"), std::string::npos) << r.output;

  // A cloud with no view to use it is a mistake worth saying.
  r = run(base_args() + " --view " + path("view.yaml") + " --out " + path("out.png") + " --cloud " + path("wall.ply"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("none of the views has it"), std::string::npos) << r.output;
}
