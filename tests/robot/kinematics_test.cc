// Forward kinematics of URDF joints, and joint updates: unknown names and NaN rejected.
#include <gtest/gtest.h>

#include <cmath>

#include "core/robot/model/urdf_loader.h"
#include "robot_test_support.h"

namespace omniview::robot {
namespace {

TEST(SpotLikeModel, HasSpotsJointNamesAndStandsAtTheRightHeight) {
  const RobotModel model = load_urdf_file(test::spot_urdf());
  EXPECT_EQ(model.links()[0].name, "body");
  ASSERT_EQ(model.variable_names().size(), 12u);
  for (const char* leg : {"fl", "fr", "hl", "hr"}) {
    for (const char* joint : {".hx", ".hy", ".kn"}) EXPECT_GE(model.variable_index(std::string(leg) + joint), 0) << leg << joint;
  }
  std::vector<double> q = model.zero_positions();
  JointPositions standing;
  for (const char* leg : {"fl", "fr", "hl", "hr"}) {
    standing[std::string(leg) + ".hx"] = 0;
    standing[std::string(leg) + ".hy"] = 0.8;
    standing[std::string(leg) + ".kn"] = -1.6;
  }
  model.apply(standing, q);
  const auto poses = model.link_poses(q);
  // The foot (the lower leg's end) under the hip, knee pointing back, body ~0.45 m above it.
  const Vec3 foot = poses[model.link_index("fl.lleg")] * Vec3(0, 0, -0.33);
  EXPECT_NEAR(foot.z(), -0.65 * std::cos(0.8), 1e-9);
  EXPECT_NEAR(foot.x(), 0.29785 + 0.01 * std::sin(0.8), 1e-9);
  EXPECT_NEAR(foot.y(), 0.165, 1e-9);
  const Vec3 knee = poses[model.link_index("fl.lleg")].translation();
  EXPECT_LT(knee.x(), 0.29785 - 0.2);
  const Vec3 hind_right_foot = poses[model.link_index("hr.lleg")] * Vec3(0, 0, -0.33);
  EXPECT_NEAR(hind_right_foot.y(), -0.165, 1e-9);
  EXPECT_NEAR(hind_right_foot.x(), -0.29785 + 0.01 * std::sin(0.8), 1e-9);
}

TEST(JointUpdates, UnknownJointIsAClearErrorAndChangesNothing) {
  const RobotModel model = load_urdf_file(test::spot_urdf());
  std::vector<double> q = model.zero_positions();
  try {
    model.apply({{"fl.hy", 0.5}, {"front_left_hip_x", 0.1}}, q);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("front_left_hip_x"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("fl.hx"), std::string::npos) << "lists the known joints: " << e.what();
  }
  EXPECT_EQ(q, model.zero_positions());
  EXPECT_THROW(model.apply({{"fl.kn", std::nan("")}}, q), std::invalid_argument);
  EXPECT_THROW(model.apply({{"fl.kn", INFINITY}}, q), std::invalid_argument);
  EXPECT_EQ(q, model.zero_positions());
  model.apply({{"fl.kn", 7.0}}, q);  // limits are not enforced
  EXPECT_EQ(q[model.variable_index("fl.kn")], 7.0);
}

constexpr const char* kJointKinds = R"(<robot name="kinds">
  <link name="base"/><link name="slider"/><link name="wheel"/><link name="arm"/><link name="twin"/><link name="tip"/>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="slider"/>
    <origin xyz="1 0 0"/><axis xyz="0 0 2"/><limit lower="0" upper="1" effort="1" velocity="1"/></joint>
  <joint name="spin" type="continuous"><parent link="slider"/><child link="wheel"/><axis xyz="0 0 1"/></joint>
  <joint name="bend" type="revolute"><parent link="wheel"/><child link="arm"/><origin xyz="0 0 0.5" rpy="0 0 1.5707963267948966"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="copy" type="revolute"><parent link="base"/><child link="twin"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="spin" multiplier="2" offset="0.1"/></joint>
  <joint name="weld" type="fixed"><parent link="arm"/><child link="tip"/><origin xyz="1 0 0"/></joint>
</robot>)";

TEST(ForwardKinematics, PrismaticContinuousRevoluteMimicAndFixed) {
  const RobotModel model = load_urdf_string(kJointKinds, ".", {}, "test URDF");
  EXPECT_EQ(model.variable_names().size(), 3u);  // slide, spin, bend; the mimic joint follows spin
  EXPECT_LT(model.variable_index("copy"), 0);
  std::vector<double> q = model.zero_positions();
  model.apply({{"slide", 0.25}, {"spin", M_PI / 4}, {"bend", M_PI / 2}}, q);
  const auto poses = model.link_poses(q);
  const auto at = [&](const char* link) { return poses[model.link_index(link)]; };
  EXPECT_TRUE(at("slider").translation().isApprox(Vec3(1, 0, 0.25)));  // axis normalised
  EXPECT_TRUE((at("wheel").linear() * Vec3::UnitX()).isApprox(Vec3(1, 1, 0).normalized()));
  // The arm starts 0.5 above the wheel; bending +90 deg about its y turns its x straight down
  // whatever the yaw above it, so the tip hangs 1 m below.
  EXPECT_TRUE(at("arm").translation().isApprox(Vec3(1, 0, 0.75)));
  EXPECT_TRUE(at("tip").translation().isApprox(Vec3(1, 0, -0.25), 1e-9)) << at("tip").translation().transpose();
  EXPECT_NEAR(Eigen::AngleAxisd(at("twin").linear()).angle(), 2 * M_PI / 4 + 0.1, 1e-9);
  EXPECT_THROW(model.link_poses({1.0}), std::invalid_argument);
}

}  // namespace
}  // namespace omniview::robot
