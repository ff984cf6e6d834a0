// Poses and the angle conventions of the API (README, "Conventions"): yaw/pitch/roll as in ROS (positive pitch
// looks down), T_A_B maps B coordinates into A, the view and optical frames.
#include "core/geometry/pose.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_support.h"

namespace omniview {
namespace {

using testing::kDeg;

bool near(const Vec3& a, const Vec3& b, double tol = 1e-12) { return (a - b).norm() < tol; }

TEST(Pose, YawPitchRollConventions) {
  // Yaw 90 turns forward (+x) to the left (+y).
  EXPECT_TRUE(near(rotation_from_ypr(90 * kDeg, 0, 0) * Vec3::UnitX(), Vec3::UnitY()));
  // Positive pitch looks down: the rotated x axis has negative z.
  for (double pitch_deg : {1.0, 30.0, 60.0}) {
    const Vec3 forward = rotation_from_ypr(0, pitch_deg * kDeg, 0) * Vec3::UnitX();
    EXPECT_LT(forward.z(), 0) << pitch_deg;
    EXPECT_NEAR(forward.z(), -std::sin(pitch_deg * kDeg), 1e-12);
  }
  EXPECT_TRUE(near(rotation_from_ypr(0, 90 * kDeg, 0) * Vec3::UnitX(), -Vec3::UnitZ()));
  // Positive roll about the viewing direction lifts the left side (+y) up.
  EXPECT_GT((rotation_from_ypr(0, 0, 20 * kDeg) * Vec3::UnitY()).z(), 0);
  // R = Rz(yaw) Ry(pitch) Rx(roll): roll first, then pitch, then yaw, about fixed axes. So a
  // view yawed left and pitched down still looks down-left, not down-forward.
  const Vec3 f = rotation_from_ypr(90 * kDeg, 30 * kDeg, 0) * Vec3::UnitX();
  EXPECT_TRUE(near(f, Vec3(0, std::cos(30 * kDeg), -std::sin(30 * kDeg))));
  const double y = 0.3, p = -0.4, r = 1.1;
  const Mat3 Rz = Eigen::AngleAxisd(y, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 Ry = Eigen::AngleAxisd(p, Vec3::UnitY()).toRotationMatrix();
  const Mat3 Rx = Eigen::AngleAxisd(r, Vec3::UnitX()).toRotationMatrix();
  EXPECT_TRUE(rotation_from_ypr(y, p, r).isApprox(Rz * Ry * Rx, 1e-14));
}

TEST(Pose, YawPitchRollRoundTrip) {
  for (double y : {-179.0, -90.0, -30.0, 0.0, 45.0, 135.0, 179.0}) {
    for (double p : {-89.0, -45.0, -10.0, 0.0, 33.0, 85.0}) {
      for (double r : {-170.0, -120.0, 0.0, 5.0, 150.0}) {
        const Mat3 R = rotation_from_ypr(y * kDeg, p * kDeg, r * kDeg);
        const Vec3 ypr = ypr_from_rotation(R);
        EXPECT_NEAR(ypr[0], y * kDeg, 1e-9) << y << " " << p << " " << r;
        EXPECT_NEAR(ypr[1], p * kDeg, 1e-9) << y << " " << p << " " << r;
        EXPECT_NEAR(ypr[2], r * kDeg, 1e-9) << y << " " << p << " " << r;
      }
    }
  }
}

TEST(Pose, YawPitchRollAtGimbalLockStillReproducesTheRotation) {
  // At pitch +-90 only yaw -+ roll is defined; whichever split is returned must rebuild R.
  for (double p : {-90.0, 90.0}) {
    for (double y : {-100.0, 0.0, 40.0}) {
      for (double r : {-30.0, 0.0, 70.0}) {
        const Mat3 R = rotation_from_ypr(y * kDeg, p * kDeg, r * kDeg);
        const Vec3 ypr = ypr_from_rotation(R);
        EXPECT_NEAR(ypr[1], p * kDeg, 1e-6);
        EXPECT_TRUE(rotation_from_ypr(ypr[0], ypr[1], ypr[2]).isApprox(R, 1e-9)) << y << " " << p << " " << r;
      }
    }
  }
}

TEST(Pose, YawPitchRollNearGimbalLockKeepsAllThreeAngles) {
  // A micro-radian short of straight down is not gimbal lock: roll must survive, and
  // pitch must not lose half its digits to asin near 1.
  for (double delta : {1e-4, 1e-6, 1e-7}) {
    for (double sign : {-1.0, 1.0}) {
      const double p = sign * (M_PI_2 - delta);
      const Vec3 ypr = ypr_from_rotation(rotation_from_ypr(0.7, p, -0.4));
      EXPECT_NEAR(ypr[1], p, 1e-12) << delta;
      EXPECT_NEAR(ypr[0], 0.7, 1e-8) << delta;
      EXPECT_NEAR(ypr[2], -0.4, 1e-8) << delta;
    }
  }
}

TEST(Pose, TransformsComposeAsTheNamesSay) {
  // p_A = T_A_B p_B, so T_A_C = T_A_B T_B_C and T_B_A = T_A_B^-1.
  const Pose T_A_B = make_pose(Vec3(1, 2, 3), 0.3, 0.2, -0.1);
  const Pose T_B_C = make_pose(Vec3(-0.5, 0.1, 0), -1.0, 0.4, 0.7);
  const Vec3 p_C(0.3, -0.2, 5);
  EXPECT_TRUE(near((T_A_B * T_B_C) * p_C, T_A_B * (T_B_C * p_C)));
  EXPECT_TRUE(near(T_A_B.inverse() * (T_A_B * p_C), p_C));
  // The origin of B sits at T_A_B's translation in A.
  EXPECT_TRUE(near(T_A_B * Vec3::Zero(), Vec3(1, 2, 3)));
  EXPECT_TRUE(make_pose(Vec3(1, 2, 3), 0.3, 0.2, -0.1).linear().isApprox(rotation_from_ypr(0.3, 0.2, -0.1)));
}

TEST(Pose, MatrixOfARigidTransformIsAccepted) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = rotation_from_ypr(0.3, 0.2, 0.1);
  m.topRightCorner<3, 1>() = Vec3(1, 2, 3);
  const Pose T = pose_from_matrix(m, "T");
  EXPECT_TRUE(T.matrix().isApprox(m, 1e-12));
  // kalibr prints 8 or so digits: the rounding is accepted and orthonormalised away, so
  // chains of such matrices stay rigid.
  Mat4 rounded = m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) rounded(r, c) = std::round(m(r, c) * 1e6) / 1e6;
  }
  const Pose Tr = pose_from_matrix(rounded, "T");
  EXPECT_LT((Tr.linear().transpose() * Tr.linear() - Mat3::Identity()).norm(), 1e-14);
  EXPECT_NEAR(Tr.linear().determinant(), 1, 1e-14);
  EXPECT_TRUE(Tr.linear().isApprox(m.topLeftCorner<3, 3>(), 1e-5));
}

TEST(Pose, MatrixMustBeRigid) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = rotation_from_ypr(0.3, 0.2, 0.1);
  m.topRightCorner<3, 1>() = Vec3(1, 2, 3);
  const auto with = [&](auto edit) {
    Mat4 b = m;
    edit(b);
    return b;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [name, bad, needle] : std::vector<std::tuple<std::string, Mat4, std::string>>{
           {"scaled", with([](Mat4& b) { b.topLeftCorner<3, 3>() *= 1.1; }), "not a rotation"},
           {"slightly scaled", with([](Mat4& b) { b.topLeftCorner<3, 3>() *= 1.001; }), "not a rotation"},
           {"sheared", with([](Mat4& b) { b(0, 1) += 0.2; }), "not a rotation"},
           {"reflected", with([](Mat4& b) { b.col(0).head<3>() *= -1; }), "det"},
           {"mirrored axes", with([](Mat4& b) { b.topLeftCorner<3, 3>() = -Mat3::Identity(); }), "det"},
           {"last row", with([](Mat4& b) { b(3, 0) = 0.5; }), "last row"},
           {"last row scale", with([](Mat4& b) { b(3, 3) = 2; }), "last row"},
           {"nan", with([&](Mat4& b) { b(1, 1) = nan; }), "non-finite"},
           {"inf translation", with([](Mat4& b) { b(2, 3) = INFINITY; }), "non-finite"}}) {
    testing::expect_throw_containing<std::invalid_argument>([&] { pose_from_matrix(bad, "cam1.T_cn_cnm1"); },
                                                            {"cam1.T_cn_cnm1", needle}, name);
  }
}

TEST(Pose, ViewToOpticalAxes) {
  const Mat3& R = R_view_optical();
  EXPECT_TRUE(near(R * Vec3::UnitZ(), Vec3::UnitX()));   // optical z (axis) = view x (forward)
  EXPECT_TRUE(near(R * Vec3::UnitX(), -Vec3::UnitY()));  // optical x (right) = view -y
  EXPECT_TRUE(near(R * Vec3::UnitY(), -Vec3::UnitZ()));  // optical y (down) = view -z
  EXPECT_NEAR(R.determinant(), 1, 1e-15);
  EXPECT_TRUE((R.transpose() * R).isApprox(Mat3::Identity()));
}

TEST(Pose, ViewPitchedStraightDownHasForwardAtTheTopOfTheImage) {
  // The convention: a view at pitch +90 looks straight down with the robot's +x at the top of
  // the image, i.e. along optical -y.
  const Mat3 R_robot_optical = rotation_from_ypr(0, 90 * kDeg, 0) * R_view_optical();
  EXPECT_TRUE(near(R_robot_optical * Vec3::UnitZ(), -Vec3::UnitZ()));  // looks down
  EXPECT_TRUE(near(R_robot_optical * -Vec3::UnitY(), Vec3::UnitX()));  // image up = forward
  EXPECT_TRUE(near(R_robot_optical * Vec3::UnitX(), -Vec3::UnitY()));  // image right = robot right
}

}  // namespace
}  // namespace omniview
