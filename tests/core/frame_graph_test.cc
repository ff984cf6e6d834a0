// FrameGraph: lookups across a forest of rigid links, live re-linking, and errors that
// name the frames involved.
#include "core/geometry/frame_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "test_support.h"

namespace omniview {
namespace {

// body -+- front
//       +- head -- cam -- lens
//       +- arm -- gripper
// world (a second tree) -- odom
FrameGraph robot() {
  FrameGraph g;
  g.set_parent("front", "body", make_pose(Vec3(0.4, 0.1, 0.0), 0.2, 0.3, 0.0));
  g.set_parent("head", "body", make_pose(Vec3(-0.2, 0.0, 0.5), 1.0, 0.0, 0.1));
  g.set_parent("cam", "head", make_pose(Vec3(0.05, 0, 0.1), -0.4, 0.2, 0.3));
  g.set_parent("lens", "cam", make_pose(Vec3(0, 0, 0.01), 0, 0, 0.5));
  g.set_parent("arm", "body", make_pose(Vec3(0.3, 0, 0.2), 0, -0.3, 0));
  g.set_parent("gripper", "arm", make_pose(Vec3(0.6, 0, 0), 0.1, 0.2, 0.3));
  g.set_parent("odom", "world", make_pose(Vec3(5, 5, 0), 2.0, 0, 0));
  return g;
}

TEST(FrameGraph, LooksUpAcrossBranches) {
  const FrameGraph g = robot();
  const Pose T_body_front = make_pose(Vec3(0.4, 0.1, 0.0), 0.2, 0.3, 0.0);
  const Pose T_body_head = make_pose(Vec3(-0.2, 0.0, 0.5), 1.0, 0.0, 0.1);
  const Pose T_head_cam = make_pose(Vec3(0.05, 0, 0.1), -0.4, 0.2, 0.3);
  const Pose T_front_cam = g.lookup("front", "cam");
  EXPECT_TRUE(T_front_cam.isApprox(T_body_front.inverse() * T_body_head * T_head_cam, 1e-12));
  // A point 1 m along the camera's axis, seen from front, by hand.
  const Vec3 p_cam(0, 0, 1);
  EXPECT_LT((T_front_cam * p_cam - T_body_front.inverse() * (T_body_head * (T_head_cam * p_cam))).norm(), 1e-12);
  EXPECT_TRUE(g.lookup("body", "body").isApprox(Pose::Identity()));
  EXPECT_TRUE(g.lookup("world", "world").isApprox(Pose::Identity()));
}

TEST(FrameGraph, InverseAndChainConsistency) {
  // For every pair and triple of connected frames: T_a_b T_b_a = I and T_a_c = T_a_b T_b_c.
  const FrameGraph g = robot();
  const std::vector<std::string> frames{"body", "front", "head", "cam", "lens", "arm", "gripper"};
  for (const auto& a : frames) {
    for (const auto& b : frames) {
      const Pose T_ab = g.lookup(a, b);
      EXPECT_TRUE((T_ab * g.lookup(b, a)).isApprox(Pose::Identity(), 1e-12)) << a << " " << b;
      for (const auto& c : frames) {
        EXPECT_TRUE(g.lookup(a, c).isApprox(T_ab * g.lookup(b, c), 1e-12)) << a << " " << b << " " << c;
      }
    }
  }
}

TEST(FrameGraph, FramesParentsAndMembership) {
  const FrameGraph g = robot();
  auto frames = g.frames();
  std::sort(frames.begin(), frames.end());
  EXPECT_EQ(frames,
            (std::vector<std::string>{"arm", "body", "cam", "front", "gripper", "head", "lens", "odom", "world"}));
  EXPECT_TRUE(g.has_frame("world")) << "a frame known only as a parent is a frame";
  EXPECT_FALSE(g.has_frame("nowhere"));
  EXPECT_EQ(g.parent_of("lens"), "cam");
  EXPECT_EQ(g.parent_of("body"), std::nullopt) << "a root";
  EXPECT_EQ(g.parent_of("nowhere"), std::nullopt);
}

TEST(FrameGraph, ReplacingALinkMovesItsSubtree) {
  // Live transforms (an arm's joint, Spot's frame tree) replace links with set_parent().
  FrameGraph g = robot();
  const Pose T_arm_gripper = g.lookup("arm", "gripper");
  g.set_parent("arm", "body", make_pose(Vec3(2, 0, 0), 0, 0, 0));
  EXPECT_TRUE(g.lookup("body", "gripper").isApprox(make_pose(Vec3(2, 0, 0), 0, 0, 0) * T_arm_gripper, 1e-12));
  // Re-parenting a subtree onto another branch is allowed when it makes no cycle.
  g.set_parent("arm", "head", Pose::Identity());
  EXPECT_TRUE(g.lookup("head", "gripper").isApprox(T_arm_gripper, 1e-12));
  // Joining the two trees makes them connected.
  EXPECT_FALSE(g.try_lookup("odom", "cam"));
  g.set_parent("body", "odom", make_pose(Vec3(1, 0, 0), 0, 0, 0));
  EXPECT_TRUE(g.try_lookup("odom", "cam"));
  EXPECT_TRUE(g.try_lookup("world", "gripper"));
}

TEST(FrameGraph, RejectsCyclesAndLeavesTheGraphUnchanged) {
  FrameGraph g = robot();
  const Pose before = g.lookup("body", "lens");
  // lens is below head: making head a child of lens closes head -> cam -> lens -> head.
  testing::expect_throw_containing<std::invalid_argument>([&] { g.set_parent("head", "lens", Pose::Identity()); },
                                                          {"'head'", "'lens'", "cycle"});
  testing::expect_throw_containing<std::invalid_argument>([&] { g.set_parent("body", "gripper", Pose::Identity()); },
                                                          {"cycle"});
  testing::expect_throw_containing<std::invalid_argument>([&] { g.set_parent("cam", "cam", Pose::Identity()); },
                                                          {"'cam'", "own parent"});
  EXPECT_THROW(g.set_parent("", "body", Pose::Identity()), std::invalid_argument);
  EXPECT_THROW(g.set_parent("x", "", Pose::Identity()), std::invalid_argument);
  EXPECT_TRUE(g.lookup("body", "lens").isApprox(before, 1e-15));
  EXPECT_EQ(g.parent_of("head"), "body");
}

TEST(FrameGraph, ErrorsNameTheFrames) {
  const FrameGraph g = robot();
  testing::expect_throw_containing<std::out_of_range>([&] { g.lookup("cam", "odom"); },
                                                      {"'cam'", "'odom'", "not connected"});
  testing::expect_throw_containing<std::out_of_range>([&] { g.lookup("cam", "nowhere"); }, {"unknown frame 'nowhere'"});
  testing::expect_throw_containing<std::out_of_range>([&] { g.lookup("nowhere", "cam"); }, {"unknown frame 'nowhere'"});
  testing::expect_throw_containing<std::out_of_range>([&] { g.lookup("ghost", "ghost"); }, {"unknown frame 'ghost'"});
  EXPECT_FALSE(g.try_lookup("cam", "odom"));
  EXPECT_FALSE(g.try_lookup("cam", "nowhere"));
  EXPECT_FALSE(FrameGraph().try_lookup("a", "a"));
}

}  // namespace
}  // namespace omniview
