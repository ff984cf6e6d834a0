// Poses, the yaw/pitch/roll convention, the view/optical axes and the frame graph.
#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry/frame_graph.h"
#include "core/geometry/pose.h"

namespace omniview {
namespace {

constexpr double kDeg = M_PI / 180;

TEST(Pose, YawPitchRollConventions) {
  // Yaw 90 turns forward (+x) to the left (+y); positive pitch looks down.
  EXPECT_TRUE((rotation_from_ypr(90 * kDeg, 0, 0) * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-12));
  EXPECT_LT((rotation_from_ypr(0, 30 * kDeg, 0) * Vec3::UnitX()).z(), 0);
  EXPECT_TRUE((rotation_from_ypr(0, 90 * kDeg, 0) * Vec3::UnitX()).isApprox(-Vec3::UnitZ(), 1e-12));
  // Roll turns about the viewing direction: left (+y) goes up for positive roll.
  EXPECT_GT((rotation_from_ypr(0, 0, 20 * kDeg) * Vec3::UnitY()).z(), 0);
}

TEST(Pose, YawPitchRollRoundTrip) {
  for (double y : {-170.0, -30.0, 0.0, 45.0, 179.0}) {
    for (double p : {-80.0, -10.0, 0.0, 33.0, 85.0}) {
      for (double r : {-120.0, 0.0, 5.0, 150.0}) {
        const Vec3 ypr = ypr_from_rotation(rotation_from_ypr(y * kDeg, p * kDeg, r * kDeg));
        EXPECT_TRUE(rotation_from_ypr(ypr[0], ypr[1], ypr[2]).isApprox(rotation_from_ypr(y * kDeg, p * kDeg, r * kDeg),
                                                                          1e-9));
        EXPECT_NEAR(ypr[1], p * kDeg, 1e-9);
      }
    }
  }
}

TEST(Pose, ViewToOpticalAxes) {
  const Mat3& R = R_view_optical();
  EXPECT_TRUE((R * Vec3::UnitZ()).isApprox(Vec3::UnitX()));    // optical z = view x
  EXPECT_TRUE((R * Vec3::UnitX()).isApprox(-Vec3::UnitY()));   // optical x (right) = view -y
  EXPECT_TRUE((R * Vec3::UnitY()).isApprox(-Vec3::UnitZ()));   // optical y (down) = view -z
  EXPECT_NEAR(R.determinant(), 1, 1e-12);
}

TEST(Pose, MatrixMustBeRigid) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = rotation_from_ypr(0.3, 0.2, 0.1);
  m.topRightCorner<3, 1>() = Vec3(1, 2, 3);
  EXPECT_TRUE(pose_from_matrix(m, "T").translation().isApprox(Vec3(1, 2, 3)));
  for (const auto& [name, bad] : std::vector<std::pair<std::string, Mat4>>{
           {"scaled", [&] { Mat4 b = m; b.topLeftCorner<3, 3>() *= 1.1; return b; }()},
           {"sheared", [&] { Mat4 b = m; b(0, 1) += 0.2; return b; }()},
           {"reflected", [&] { Mat4 b = m; b.col(0) *= -1; return b; }()},
           {"last row", [&] { Mat4 b = m; b(3, 0) = 0.5; return b; }()},
           {"nan", [&] { Mat4 b = m; b(1, 1) = NAN; return b; }()}}) {
    try {
      pose_from_matrix(bad, "cam1.T_cn_cnm1");
      ADD_FAILURE() << name << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("cam1.T_cn_cnm1"), std::string::npos) << e.what();
    }
  }
}

TEST(FrameGraph, LooksUpAcrossBranches) {
  FrameGraph g;
  const Pose T_body_front = make_pose(Vec3(0.4, 0.1, 0.0), 0.2, 0.3, 0.0);
  const Pose T_body_head = make_pose(Vec3(-0.2, 0.0, 0.5), 1.0, 0.0, 0.1);
  const Pose T_head_cam = make_pose(Vec3(0.05, 0, 0.1), -0.4, 0.2, 0.3);
  g.set_parent("front", "body", T_body_front);
  g.set_parent("head", "body", T_body_head);
  g.set_parent("cam", "head", T_head_cam);
  const Pose T_front_cam = g.lookup("front", "cam");
  EXPECT_TRUE(T_front_cam.isApprox(T_body_front.inverse() * T_body_head * T_head_cam, 1e-12));
  EXPECT_TRUE(g.lookup("cam", "front").isApprox(T_front_cam.inverse(), 1e-12));
  EXPECT_TRUE(g.lookup("body", "body").isApprox(Pose::Identity()));
}

TEST(FrameGraph, ReplacingALinkMovesItsSubtree) {
  FrameGraph g;
  g.set_parent("arm", "body", make_pose(Vec3(1, 0, 0), 0, 0, 0));
  g.set_parent("gripper", "arm", make_pose(Vec3(0.5, 0, 0), 0, 0, 0));
  EXPECT_NEAR(g.lookup("body", "gripper").translation().x(), 1.5, 1e-12);
  g.set_parent("arm", "body", make_pose(Vec3(2, 0, 0), 0, 0, 0));
  EXPECT_NEAR(g.lookup("body", "gripper").translation().x(), 2.5, 1e-12);
}

TEST(FrameGraph, ErrorsNameTheFrames) {
  FrameGraph g;
  g.set_parent("a", "b", Pose::Identity());
  g.set_parent("c", "d", Pose::Identity());
  EXPECT_THROW(g.set_parent("b", "a", Pose::Identity()), std::invalid_argument);  // cycle
  EXPECT_THROW(g.set_parent("a", "a", Pose::Identity()), std::invalid_argument);
  try {
    g.lookup("a", "c");
    ADD_FAILURE();
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("'a' and 'c' are not connected"), std::string::npos) << e.what();
  }
  try {
    g.lookup("a", "nowhere");
    ADD_FAILURE();
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("unknown frame 'nowhere'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace omniview
