// body in odom from a frame-tree snapshot's edges (the motion a cloud's time sync uses).
#include "spot_adapter/source/body_motion.h"

#include <gtest/gtest.h>

namespace omniview::spot {
namespace {

TEST(BodyMotion, BodyInOdomFromTheSnapshot) {
  const Pose T_body_odom = make_pose(Vec3(-1, 2, -0.5), 0.3, 0, 0);
  const Pose T_body_camera = make_pose(Vec3(0.4, 0, 0.1), 0, 0.2, 0);
  const std::vector<FrameEdge> edges = {{"odom", "body", T_body_odom}, {"cam", "body", T_body_camera}};
  const auto T_odom_body = pose_in_snapshot(edges, "odom", "body");
  ASSERT_TRUE(T_odom_body);
  EXPECT_TRUE(T_odom_body->isApprox(T_body_odom.inverse(), 1e-12));
  // Through a common parent other than the body.
  const auto T_odom_cam = pose_in_snapshot(edges, "odom", "cam");
  ASSERT_TRUE(T_odom_cam);
  EXPECT_TRUE(T_odom_cam->isApprox(T_body_odom.inverse() * T_body_camera, 1e-12));
  EXPECT_FALSE(pose_in_snapshot(edges, "vision", "body")) << "a frame the snapshot lacks";
  EXPECT_FALSE(pose_in_snapshot({{"a", "b", Pose::Identity()}, {"b", "a", Pose::Identity()}}, "a", "odom"));
  EXPECT_FALSE(pose_in_snapshot({{"a", "b", Pose::Identity()}, {"b", "a", Pose::Identity()}}, "a", "b"))
      << "a cycle gives no pose, not a hang";
}

}  // namespace
}  // namespace omniview::spot
