// Rig YAML and kalibr camchains: chains compose, and every error names file, line and key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "core/io/yaml_reader.h"
#include "core/rig/rig.h"

namespace omniview {
namespace {

namespace fs = std::filesystem;

class RigFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("omniview_rig_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  // Loads and expects a ConfigError containing every needle.
  void expect_error(const std::string& file, std::initializer_list<std::string> needles) {
    try {
      load_rig(file);
      ADD_FAILURE() << file << " loaded";
    } catch (const ConfigError& e) {
      for (const auto& n : needles) EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << e.what();
    }
  }
  fs::path dir_;
};

std::string mat4_yaml(const Pose& T) {
  std::ostringstream os;
  os.precision(17);
  const Mat4 m = T.matrix();
  for (int r = 0; r < 4; ++r) os << "  - [" << m(r, 0) << ", " << m(r, 1) << ", " << m(r, 2) << ", " << m(r, 3) << "]\n";
  return os.str();
}

std::string camchain_entry(int n, const Pose* T_cn_cnm1) {
  std::string s = "cam" + std::to_string(n) + ":\n";
  if (T_cn_cnm1) s += "  T_cn_cnm1:\n" + mat4_yaml(*T_cn_cnm1);
  s += "  camera_model: pinhole\n  intrinsics: [400, 400, 320, 240]\n  distortion_model: radtan\n"
       "  distortion_coeffs: [-0.1, 0.01, 0.0, 0.0]\n  resolution: [640, 480]\n  rostopic: /cam/image_raw\n";
  return s;
}

TEST_F(RigFiles, CamchainsOfTwoToFiveComposeCorrectly) {
  const Pose T_base_cam0 = make_pose(Vec3(0.3, -0.1, 1.2), -1.6, 0.1, -1.5);
  for (int count = 2; count <= 5; ++count) {
    std::vector<Pose> truth{T_base_cam0};
    for (int i = 1; i < count; ++i) {
      truth.push_back(truth.back() * make_pose(Vec3(0.1 * i, 0.02, -0.03 * i), 0.4 * i, -0.1, 0.05 * i));
    }
    std::string text;
    for (int i = 0; i < count; ++i) {
      // p_cn = T_cn_cnm1 p_cnm1, so T_cn_cnm1 = T_base_cn^-1 T_base_cnm1.
      const Pose T = i ? truth[i].inverse() * truth[i - 1] : Pose::Identity();
      text += camchain_entry(i, i ? &T : nullptr);
    }
    const Rig rig = load_kalibr_camchain(write("camchain.yaml", text), "base_link", T_base_cam0);
    ASSERT_EQ(rig.cameras().size(), static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) {
      EXPECT_TRUE(rig.camera_pose("base_link", i).isApprox(truth[i], 1e-9)) << count << " cameras, cam" << i;
      EXPECT_EQ(rig.cameras()[i].name, "cam" + std::to_string(i));
    }
  }
}

TEST_F(RigFiles, LoadRigTellsTheFormatsApart) {
  const Pose I = Pose::Identity();
  EXPECT_EQ(load_rig(write("chain.yaml", camchain_entry(0, nullptr) + camchain_entry(1, &I))).cameras().size(), 2u);
  EXPECT_EQ(load_rig(write("rig.yaml", "cameras:\n  - {name: a, camera_model: pinhole, intrinsics: [1, 1, 0, 0], "
                                       "resolution: [4, 4], mount: {xyz: [0, 0, 0]}}\n"))
                .cameras()
                .size(),
            1u);
}

TEST_F(RigFiles, OurRigFormat) {
  cv::imwrite((dir_ / "mask.png").string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(255)));
  const Rig rig = load_rig(write("rig.yaml", R"(frame: body
frames:
  - {name: head, parent: body, T_parent_frame: {xyz: [0.1, 0, 0.5], ypr_deg: [90, 0, 0]}}
cameras:
  - name: left
    camera_model: omni
    intrinsics: [0.9, 300, 300, 320, 240]
    distortion_model: radtan
    distortion_coeffs: [-0.2, 0.05, 0, 0, 0.001]
    resolution: [640, 480]
    parent: head
    mount: {xyz: [0, 0, 0.1], ypr_deg: [0, 10, 0]}
    mask: mask.png
    fov_deg: 190
  - name: right
    camera_model: eucm
    intrinsics: [0.6, 1.1, 300, 300, 320, 240]
    resolution: [640, 480]
    T_parent_cam: {xyz: [0, -0.1, 0], quat_xyzw: [0, 0, 0, 1]}
)"));
  ASSERT_EQ(rig.cameras().size(), 2u);
  EXPECT_EQ(rig.default_frame(), "body");
  EXPECT_EQ(rig.cameras()[0].mask.cols, 640);
  EXPECT_EQ(rig.cameras()[0].fov_deg, 190);
  // mount: the optical axis of "left" points along head's x, pitched 10 deg down; head is
  // yawed 90 deg, so in body the axis points along +y and slightly down.
  const Vec3 axis = rig.camera_pose("body", 0).linear() * Vec3::UnitZ();
  EXPECT_NEAR(axis.y(), std::cos(10 * M_PI / 180), 1e-9);
  EXPECT_NEAR(axis.z(), -std::sin(10 * M_PI / 180), 1e-9);
  EXPECT_TRUE(rig.camera_pose("body", 1).translation().isApprox(Vec3(0, -0.1, 0)));
}

TEST_F(RigFiles, ErrorsNameFileLineAndKey) {
  const std::string good_cam =
      "  - name: a\n    camera_model: pinhole\n    intrinsics: [1, 1, 0, 0]\n    resolution: [4, 4]\n"
      "    mount: {xyz: [0, 0, 0]}\n";
  expect_error(write("typo.yaml", "cameras:\n  - name: a\n    camera_modle: pinhole\n"),
               {"typo.yaml:3", "camera_modle", "unknown key"});
  expect_error(write("missing.yaml", "cameras:\n  - name: a\n    camera_model: pinhole\n    resolution: [4, 4]\n"),
               {"missing.yaml:", "cameras[0] (a)", "missing required key 'intrinsics'"});
  expect_error(write("count.yaml", "cameras:\n  - name: a\n    camera_model: ds\n    intrinsics: [1, 2]\n"
                                   "    resolution: [4, 4]\n    mount: {}\n"),
               {"count.yaml:", "intrinsics needs 6 values"});
  expect_error(write("unknown.yaml", "cameras:\n  - name: a\n    camera_model: scaramuzza\n    intrinsics: [1]\n"
                                     "    resolution: [4, 4]\n    mount: {}\n"),
               {"unknown.yaml:", "unknown camera_model 'scaramuzza'"});
  expect_error(write("rigid.yaml", "cameras:\n  - name: a\n    camera_model: pinhole\n    intrinsics: [1, 1, 0, 0]\n"
                                   "    resolution: [4, 4]\n    T_parent_cam:\n      - [2, 0, 0, 0]\n"
                                   "      - [0, 1, 0, 0]\n      - [0, 0, 1, 0]\n      - [0, 0, 0, 1]\n"),
               {"rigid.yaml:7", "T_parent_cam", "not a rotation"});
  expect_error(write("dup.yaml", "cameras:\n" + good_cam + good_cam), {"dup.yaml:", "defined twice"});
  cv::imwrite((dir_ / "small.png").string(), cv::Mat(2, 2, CV_8UC1, cv::Scalar(255)));
  expect_error(write("mask.yaml", "cameras:\n" + good_cam + "    mask: small.png\n"), {"mask.yaml:", "mask must be"});
  expect_error(write("nomask.yaml", "cameras:\n" + good_cam + "    mask: none.png\n"),
               {"nomask.yaml:", "cannot read mask image"});
  expect_error(write("syntax.yaml", "cameras: [\n  - name: a\n"), {"syntax.yaml:", "YAML syntax error"});
  expect_error((dir_ / "absent.yaml").string(), {"absent.yaml", "cannot open file"});
  expect_error(write("nan.yaml", "cameras:\n  - name: a\n    camera_model: pinhole\n    intrinsics: [1, .nan, 0, 0]\n"
                                 "    resolution: [4, 4]\n    mount: {}\n"),
               {"nan.yaml:4", "intrinsics[1]", "finite"});
}

TEST_F(RigFiles, CamchainErrorsNameFileAndKey) {
  const Pose I = Pose::Identity();
  expect_error(write("gap.yaml", camchain_entry(0, nullptr) + camchain_entry(2, &I)), {"gap.yaml", "without gaps"});
  expect_error(write("extra.yaml", camchain_entry(0, nullptr) + "imu0: {}\n"), {"extra.yaml:", "imu0"});
  std::string bad = camchain_entry(0, nullptr) + camchain_entry(1, &I);
  bad.replace(bad.find("[1, 0, 0, 0]"), 12, "[1, 0, 0, 0, 5]");
  expect_error(write("bad_t.yaml", bad), {"bad_t.yaml:", "cam1.T_cn_cnm1[0]", "expected 4 numbers"});
  expect_error(write("no_t.yaml", camchain_entry(0, nullptr) + camchain_entry(1, nullptr)),
               {"no_t.yaml:", "cam1", "missing required key 'T_cn_cnm1'"});
}

}  // namespace
}  // namespace omniview
