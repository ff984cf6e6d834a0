// RobotOverlay renders only when joints, the robot's pose or the camera change, and its
// outline rings the silhouette.
#include <gtest/gtest.h>

#include <thread>

#include <opencv2/imgproc.hpp>

#include "core/robot/model/urdf_loader.h"
#include "core/robot/overlay/robot_overlay.h"
#include "robot_test_support.h"

namespace omniview::robot {
namespace {

class OverlayCache : public ::testing::Test {
 protected:
  std::shared_ptr<const RobotModel> model_ = std::make_shared<const RobotModel>(load_urdf_file(test::spot_urdf()));
  ViewSpec spec_ = test::birdseye_view(160, 120, 70, 0, 0, 2.5, 0, 90);
  PinholeCamera camera_ = pinhole_camera_of(spec_);
  Pose pose_ = T_frame_optical(spec_);
};

TEST_F(OverlayCache, RendersOnlyWhenAnInputChanges) {
  RobotOverlay overlay(model_);
  overlay.set_joint_positions({{"fl.hy", 0.8}, {"fl.kn", -1.6}});
  const OverlayLayer& first = overlay.layer(camera_, pose_);
  const uchar* pixels = first.bgra.data;
  EXPECT_EQ(overlay.render_count(), 1);
  EXPECT_FALSE(first.bbox.empty());

  overlay.layer(camera_, pose_);
  overlay.set_joint_positions({{"fl.hy", 0.8}});            // the same value
  overlay.set_joint_positions({{"fl.kn", -1.6 + 1e-6}});    // below the threshold
  Pose nudged = pose_;
  nudged.translation().x() += 1e-6;
  EXPECT_EQ(overlay.layer(camera_, nudged).bgra.data, pixels);
  EXPECT_EQ(overlay.render_count(), 1);

  overlay.set_joint_positions({{"fl.kn", -1.2}});
  overlay.layer(camera_, pose_);
  EXPECT_EQ(overlay.render_count(), 2);

  Pose moved = pose_;
  moved.translation().y() += 0.05;  // the robot moved relative to the view
  overlay.layer(camera_, moved);
  EXPECT_EQ(overlay.render_count(), 3);
  overlay.layer(camera_, moved * Eigen::AngleAxisd(0.01, Vec3::UnitZ()));
  EXPECT_EQ(overlay.render_count(), 4);

  PinholeCamera zoomed = camera_;
  zoomed.fx = zoomed.fy = camera_.fx * 1.1;
  overlay.layer(zoomed, moved);
  EXPECT_EQ(overlay.render_count(), 5);
  PinholeCamera resized{200, 100, camera_.fx, camera_.fy, 99.5, 49.5};
  EXPECT_EQ(overlay.layer(resized, moved).bgra.size(), cv::Size(200, 100));
  EXPECT_EQ(overlay.render_count(), 6);

  overlay.set_style(OverlayStyle{2});
  overlay.layer(resized, moved);
  EXPECT_EQ(overlay.render_count(), 7);

  // A rejected update changes nothing, so nothing re-renders.
  EXPECT_THROW(overlay.set_joint_positions({{"fl.kn", 0.0}, {"no.such", 1.0}}), std::invalid_argument);
  overlay.layer(resized, moved);
  EXPECT_EQ(overlay.render_count(), 7);
}

// A view placed inside the body (as the robot's own front cameras are) sees out of it: the
// body is not drawn as walls filling the view, the rest of the robot still is.
TEST_F(OverlayCache, ACameraInsideThePartSeesOutOfIt) {
  RobotOverlay overlay(model_);
  overlay.set_joint_positions({{"fl.hy", 0.8}, {"fl.kn", -1.6}, {"fr.hy", 0.8}, {"fr.kn", -1.6}});
  // In the body box, 0.42 m ahead of its centre, looking back and down at the legs.
  const ViewSpec inside = test::birdseye_view(160, 120, 100, 0.42, 0, 0, 180, 60);
  const OverlayLayer& layer = overlay.layer(pinhole_camera_of(inside), T_frame_optical(inside));
  std::vector<cv::Mat> channels;
  cv::split(layer.bgra, channels);
  const double covered = cv::countNonZero(channels[3]) / static_cast<double>(layer.bgra.total());
  EXPECT_LT(covered, 0.6) << "the body's inside would cover everything";
  EXPECT_GT(covered, 0.01) << "the legs are still drawn";
}

TEST_F(OverlayCache, OutlineRingsTheSilhouette) {
  RobotOverlay plain(model_), outlined(model_, OverlayStyle{2, cv::Scalar(10, 20, 30)});
  const OverlayLayer a = plain.layer(camera_, pose_);
  const OverlayLayer& b = outlined.layer(camera_, pose_);
  const cv::Mat mask_a = test::alpha_mask(a.bgra), mask_b = test::alpha_mask(b.bgra);
  cv::Mat grown;
  cv::dilate(mask_a, grown, cv::getStructuringElement(cv::MORPH_RECT, {5, 5}));
  EXPECT_EQ(cv::countNonZero(mask_b != grown), 0);
  EXPECT_EQ(b.bbox, cv::boundingRect(mask_b));
  EXPECT_EQ(b.bbox, (a.bbox + cv::Point(-2, -2) + cv::Size(4, 4)));
  // The robot itself is untouched; the ring has the outline colour.
  cv::Mat robot_a, robot_b;
  a.bgra.copyTo(robot_a, mask_a);
  b.bgra.copyTo(robot_b, mask_a);
  EXPECT_EQ(cv::norm(robot_a, robot_b, cv::NORM_INF), 0);
  std::vector<cv::Point> ring;
  cv::findNonZero(mask_b & ~mask_a, ring);
  ASSERT_FALSE(ring.empty());
  for (const auto& p : ring) ASSERT_EQ(b.bgra.at<cv::Vec4b>(p), cv::Vec4b(10, 20, 30, 255));
}

TEST_F(OverlayCache, RobotOutOfSightGivesAnEmptyLayer) {
  RobotOverlay overlay(model_);
  Pose away = pose_;
  away.translation().z() = -5;  // below the robot, looking down: it is behind the camera
  const OverlayLayer& layer = overlay.layer(camera_, away);
  EXPECT_TRUE(layer.bbox.empty());
  EXPECT_EQ(cv::countNonZero(test::alpha_mask(layer.bgra)), 0);
}

// OSMesa is not thread-safe; the renderers' shared lock must make concurrent overlays safe.
TEST_F(OverlayCache, OverlaysOnSeveralThreads) {
  RobotOverlay reference(model_);
  const cv::Mat expected = reference.layer(camera_, pose_).bgra.clone();
  int mismatches[2] = {0, 0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t) {
    threads.emplace_back([&, t] {
      RobotOverlay overlay(model_);
      for (int i = 0; i < 4; ++i) {
        overlay.set_joint_positions({{"fl.kn", i % 2 ? -1.0 : 0.0}});
        const cv::Mat layer = overlay.layer(camera_, pose_).bgra;
        if (i % 2 == 0) mismatches[t] += cv::norm(layer, expected, cv::NORM_INF) != 0;
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(mismatches[0] + mismatches[1], 0);
}

}  // namespace
}  // namespace omniview::robot
