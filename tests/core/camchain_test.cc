// kalibr camchains: T_cn_cnm1 chains compose to the right poses, errors name file and key,
// and load_rig() tells camchains from our rig format by content.
#include <gtest/gtest.h>

#include <sstream>

#include "core/io/yaml_reader.h"
#include "core/rig/rig.h"
#include "test_support.h"

namespace omniview {
namespace {

using testing::expect_throw_containing;

std::string mat4_yaml(const Pose& T) {
  std::ostringstream os;
  os.precision(17);
  const Mat4 m = T.matrix();
  for (int r = 0; r < 4; ++r)
    os << "  - [" << m(r, 0) << ", " << m(r, 1) << ", " << m(r, 2) << ", " << m(r, 3) << "]\n";
  return os.str();
}

// One camera of a camchain as kalibr writes it (T_cn_cnm1 for all but cam0).
std::string camchain_entry(int n, const Pose* T_cn_cnm1) {
  std::string s = "cam" + std::to_string(n) + ":\n";
  if (T_cn_cnm1) s += "  T_cn_cnm1:\n" + mat4_yaml(*T_cn_cnm1);
  s += "  cam_overlaps: [" + std::to_string(n ? n - 1 : 1) +
       "]\n"
       "  camera_model: pinhole\n"
       "  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n"
       "  distortion_model: radtan\n"
       "  intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
       "  resolution: [752, 480]\n"
       "  rostopic: /cam" +
       std::to_string(n) + "/image_raw\n";
  return s;
}

// Ground truth T_frame_camN for a chain of `count` cameras around a robot, and the
// camchain text kalibr would write for it.
std::vector<Pose> truth_poses(const Pose& T_frame_cam0, int count) {
  std::vector<Pose> truth{T_frame_cam0};
  for (int i = 1; i < count; ++i) {
    // Each camera turned further round and offset, so errors in order or inversion show.
    truth.push_back(T_frame_cam0 * make_pose(Vec3(0.3 * std::cos(1.2 * i), 0.3 * std::sin(1.2 * i), 0.1 * i),
                                             1.2 * i + 0.1, 0.2 - 0.05 * i, 0.03 * i));
  }
  return truth;
}

std::string camchain_text(const std::vector<Pose>& truth) {
  std::string text;
  for (size_t i = 0; i < truth.size(); ++i) {
    // p_cn = T_cn_cnm1 p_cnm1, so T_cn_cnm1 = T_frame_cn^-1 T_frame_cnm1.
    const Pose T = i ? truth[i].inverse() * truth[i - 1] : Pose::Identity();
    text += camchain_entry(static_cast<int>(i), i ? &T : nullptr);
  }
  return text;
}

class Camchain : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) { return dir_.write(name, text); }
  void expect_error(const std::string& name, const std::string& text, std::initializer_list<std::string> needles) {
    const std::string file = write(name, text);
    expect_throw_containing<ConfigError>([&] { load_kalibr_camchain(file, "base_link", Pose::Identity()); }, needles,
                                         name);
    expect_throw_containing<ConfigError>([&] { load_rig(file); }, needles, name + " via load_rig");
  }
  testing::TempDir dir_;
};

TEST_F(Camchain, ChainsOfTwoToFiveComposeCorrectly) {
  // A non-identity T_frame_cam0: the rig-to-robot transform the user supplies.
  const Pose T_base_cam0 = make_pose(Vec3(0.3, -0.1, 1.2), -1.6, 0.1, -1.5);
  for (int count = 2; count <= 5; ++count) {
    const std::vector<Pose> truth = truth_poses(T_base_cam0, count);
    const std::string file = write("camchain_" + std::to_string(count) + ".yaml", camchain_text(truth));
    const Rig rig = load_kalibr_camchain(file, "base_link", T_base_cam0);
    ASSERT_EQ(rig.cameras().size(), static_cast<size_t>(count));
    EXPECT_EQ(rig.default_frame(), "base_link");
    for (int i = 0; i < count; ++i) {
      const Pose got = rig.camera_pose("base_link", i);
      EXPECT_LT((got.matrix() - truth[i].matrix()).cwiseAbs().maxCoeff(), 1e-9) << count << " cameras, cam" << i;
      EXPECT_EQ(rig.cameras()[i].name, "cam" + std::to_string(i));
      EXPECT_EQ(rig.cameras()[i].width, 752);
      EXPECT_EQ(rig.cameras()[i].height, 480);
      // And relative to each other, the chain's own links come back.
      if (i > 0) {
        const Pose T_cn_cnm1 = rig.frames().lookup(rig.cameras()[i].name, rig.cameras()[i - 1].name);
        EXPECT_TRUE(T_cn_cnm1.isApprox(truth[i].inverse() * truth[i - 1], 1e-9));
      }
    }
  }
}

TEST_F(Camchain, CamerasAreOrderedByNumberNotByFilePosition) {
  // YAML maps are unordered; kalibr happens to write cam0 first, but a hand-edited file may not.
  const std::vector<Pose> truth = truth_poses(Pose::Identity(), 3);
  const Pose T10 = truth[1].inverse() * truth[0], T21 = truth[2].inverse() * truth[1];
  const Rig rig = load_kalibr_camchain(
      write("shuffled.yaml", camchain_entry(2, &T21) + camchain_entry(0, nullptr) + camchain_entry(1, &T10)), "body",
      Pose::Identity());
  ASSERT_EQ(rig.cameras().size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(rig.cameras()[i].name, "cam" + std::to_string(i));
    EXPECT_TRUE(rig.camera_pose("body", i).isApprox(truth[i], 1e-9)) << i;
  }
}

TEST_F(Camchain, LoadRigDispatchesOnContent) {
  // The file name says nothing: a camchain called rig.yaml is still a camchain, and the
  // frame and T_frame_cam0 given to load_rig() are used for it.
  const Pose T_body_cam0 = make_pose(Vec3(0, 0, 1), 0.5, 0, 0);
  const std::vector<Pose> truth = truth_poses(T_body_cam0, 2);
  const Rig chain = load_rig(write("rig.yaml", camchain_text(truth)), "body", T_body_cam0);
  ASSERT_EQ(chain.cameras().size(), 2u);
  EXPECT_EQ(chain.default_frame(), "body");
  EXPECT_TRUE(chain.camera_pose("body", 1).isApprox(truth[1], 1e-9));
  // And our format called camchain.yaml is our format.
  const Rig ours = load_rig(write("camchain.yaml",
                                  "frame: odom\ncameras:\n  - {name: a, camera_model: pinhole, "
                                  "intrinsics: [1, 1, 0, 0], resolution: [4, 4], mount: {xyz: [1, 0, 0]}}\n"),
                            "ignored", Pose::Identity());
  ASSERT_EQ(ours.cameras().size(), 1u);
  EXPECT_EQ(ours.cameras()[0].name, "a");
  EXPECT_EQ(ours.default_frame(), "odom");
  EXPECT_TRUE(ours.camera_pose("odom", 0).translation().isApprox(Vec3(1, 0, 0)));
}

TEST_F(Camchain, AcceptsWhatKalibrWritesForImuCalibrations) {
  const Pose I = Pose::Identity();
  const std::string text = camchain_entry(0, nullptr) + "  T_cam_imu:\n" + mat4_yaml(I) +
                           "  timeshift_cam_imu: 0.0012\n" + camchain_entry(1, &I);
  EXPECT_EQ(load_kalibr_camchain(write("imu.yaml", text), "imu", I).cameras().size(), 2u);
}

TEST_F(Camchain, GapsNameTheKey) {
  const Pose I = Pose::Identity();
  expect_error("gap.yaml", camchain_entry(0, nullptr) + camchain_entry(2, &I),
               {"gap.yaml:", "cam2", "cam1 is missing"});
  // The line is cam2's.
  expect_error("gap_line.yaml", camchain_entry(0, nullptr) + camchain_entry(1, &I) + camchain_entry(3, &I),
               {"gap_line.yaml:22: cam3", "cam2 is missing"});
}

TEST_F(Camchain, UnknownKeysNameFileLineAndKey) {
  const Pose I = Pose::Identity();
  expect_error("extra.yaml", camchain_entry(0, nullptr) + "imu0: {}\n",
               {"extra.yaml:9: imu0", "unexpected top-level key"});
  // Prefixes of camN are not camN.
  expect_error("camera.yaml", camchain_entry(0, nullptr) + "camera_info: {}\n",
               {"camera.yaml:9: camera_info", "unexpected top-level key"});
  expect_error("cam01.yaml", camchain_entry(0, nullptr) + "cam01: {}\n", {"cam01.yaml:9: cam01", "unexpected"});
  expect_error("dup.yaml", camchain_entry(0, nullptr) + camchain_entry(1, &I) + camchain_entry(1, &I),
               {"dup.yaml:", "cam1", "twice"});
  // Inside a camera, unknown keys are fine (below), a repeated one is not: yaml-cpp would use the first.
  expect_error("dup_key.yaml", camchain_entry(0, nullptr) + "  resolution: [640, 480]\n",
               {"dup_key.yaml:9: cam0.resolution: key given twice"});
  expect_error("not_map.yaml", "cam0: [1, 2]\n", {"not_map.yaml:1: cam0: expected a map"});
}

TEST_F(Camchain, CameraEntriesMayCarryKeysWeDoNotUse) {
  // Kalibr versions and tools add their own keys (and users their typos, which we cannot
  // tell apart); the keys we read are still checked.
  const Pose I = Pose::Identity();
  const std::string text = camchain_entry(0, nullptr) +
                           "  T_imu_cam:\n" + mat4_yaml(I) + "  line_delay: 0.0\n  rostpoic: /typo\n"
                           "  projection_model: extra\n  intrinsics_extra: {a: 1}\n" +
                           camchain_entry(1, &I);
  const Rig rig = load_kalibr_camchain(write("extra_keys.yaml", text), "base_link", I);
  ASSERT_EQ(rig.cameras().size(), 2u);
  EXPECT_EQ(rig.cameras()[0].width, 752);
}

TEST_F(Camchain, BadTransformsNameFileAndKey) {
  const Pose I = Pose::Identity();
  std::string extra_col = camchain_entry(0, nullptr) + camchain_entry(1, &I);
  extra_col.replace(extra_col.find("[1, 0, 0, 0]"), 12, "[1, 0, 0, 0, 5]");
  expect_error("bad_t.yaml", extra_col, {"bad_t.yaml:11: cam1.T_cn_cnm1[0]", "expected 4 numbers"});
  std::string scaled = camchain_entry(0, nullptr) + camchain_entry(1, &I);
  scaled.replace(scaled.find("[1, 0, 0, 0]"), 12, "[1.5, 0, 0, 0]");
  expect_error("scaled.yaml", scaled, {"scaled.yaml:11", "cam1.T_cn_cnm1", "not a rotation"});
  expect_error("no_t.yaml", camchain_entry(0, nullptr) + camchain_entry(1, nullptr),
               {"no_t.yaml:10: cam1: missing required key 'T_cn_cnm1'"});
  std::string wrong_model = camchain_entry(0, nullptr) + camchain_entry(1, &I);
  wrong_model.replace(wrong_model.rfind("camera_model: pinhole"), 21, "camera_model: omni");
  expect_error("model.yaml", wrong_model, {"model.yaml:19: cam1: intrinsics needs 5 values"});
}

TEST_F(Camchain, NotACamchain) {
  expect_throw_containing<ConfigError>(
      [&] { load_kalibr_camchain(write("rig.yaml", "cameras: []\n"), "base_link", Pose::Identity()); },
      {"rig.yaml", "not a kalibr camchain"});
  expect_throw_containing<ConfigError>([&] { load_kalibr_camchain(dir_ / "absent.yaml", "b", Pose::Identity()); },
                                       {"absent.yaml", "cannot open file"});
}

}  // namespace
}  // namespace omniview
