// Gain compensation's parts on hand-made maps and statistics: the least-squares gains,
// their smoothing over frames, the gains applied by apply_map, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>

#include "core/gain/gain_compensator.h"
#include "core/gain/gain_estimate.h"
#include "core/gain/overlap_samples.h"
#include "core/map/apply.h"

namespace omniview {
namespace {

OverlapStats stats(int cameras) {
  OverlapStats s;
  s.cameras = cameras, s.channels = 1;
  s.count.assign(static_cast<size_t>(cameras) * cameras, 0);
  s.sum.assign(s.count.size(), 0);
  return s;
}

void overlap(OverlapStats& s, int i, int j, double n, double mean_i, double mean_j) {
  s.count[s.index(0, i, j)] = s.count[s.index(0, j, i)] = n;
  s.sum[s.index(0, i, j)] = n * mean_i;
  s.sum[s.index(0, j, i)] = n * mean_j;
}

TEST(SolveGains, EqualiseOverlapsUpToTheirCommonScale) {
  OverlapStats s = stats(3);
  overlap(s, 0, 1, 1000, 70, 130);  // camera 1 exposed 1.86x brighter than camera 0
  const CameraGains g = solve_gains(s);
  ASSERT_EQ(g.cameras(), 3u);
  EXPECT_NEAR(g.at(0, 0) * 70 / (g.at(1, 0) * 130), 1.0, 0.03);
  EXPECT_GT(g.at(0, 0), 1);  // the prior keeps the pair's mean brightness between the two
  EXPECT_LT(g.at(1, 0), 1);
  EXPECT_FLOAT_EQ(g.at(2, 0), 1);  // no overlap: nothing to correct
}

TEST(SolveGains, AgreeingCamerasAndNoSamplesKeepGainsOfOne) {
  OverlapStats s = stats(2);
  overlap(s, 0, 1, 500, 120, 120);
  for (float g : solve_gains(s).gain) EXPECT_NEAR(g, 1, 1e-6);
  for (float g : solve_gains(stats(4)).gain) EXPECT_FLOAT_EQ(g, 1);
}

TEST(SolveGains, MisregisteredSamplesDoNotMoveTheMedianRatio) {
  // 60 % of the samples show the scene on the surface (ratio 70 : 130 exactly); 40 % show a
  // floor off it, where camera 0 happens to see 35 % brighter patches than camera 1.
  OverlapStats s = stats(2);
  s.log_ratio.assign(s.count.size(), {});
  const float registered = std::log(70.0f / 130.0f);
  cv::RNG rng(3);
  for (int k = 0; k < 1000; ++k) {
    s.log_ratio[s.index(0, 0, 1)].push_back(k < 600 ? registered : registered + 0.3f + float(rng.gaussian(0.1)));
  }
  overlap(s, 0, 1, 1000, 0.6 * 70 + 0.4 * 70 * 1.35, 130);  // the means carry the floor's bias
  const CameraGains g = solve_gains(s);
  EXPECT_NEAR(g.at(0, 0) * 70 / (g.at(1, 0) * 130), 1.0, 0.03);
  // Without the ratios, the means alone are 14 % off.
  s.log_ratio.clear();
  const CameraGains biased = solve_gains(s);
  EXPECT_GT(std::abs(biased.at(0, 0) * 70 / (biased.at(1, 0) * 130) - 1.0), 0.08);
}

TEST(SolveGains, AChainOfOverlapsIsSolvedJointly) {
  // 0 overlaps 1, 1 overlaps 2: camera 2 is corrected through camera 1.
  OverlapStats s = stats(3);
  overlap(s, 0, 1, 1000, 100, 125);
  overlap(s, 1, 2, 1000, 125, 150);
  const CameraGains g = solve_gains(s);
  EXPECT_NEAR(g.at(0, 0) * 100 / (g.at(2, 0) * 150), 1.0, 0.05);
}

// Two 16x16 cameras seen by every pixel of a 4x4 blend view, camera 0 primary.
FusionMap overlapping_map() {
  FusionMap map;
  map.width = map.height = 4;
  map.fusion = Fusion::kBlend;
  map.camera_sizes = {cv::Size(16, 16), cv::Size(16, 16)};
  map.camera_names = {"a", "b"};
  map.camera_used = {true, true};
  for (int i = 0; i < 16; ++i) {
    map.primary.push_back(MapEntry{static_cast<uint32_t>(i * 17 % 200), 0, 0, 0, 0});
    map.secondary.push_back(MapEntry{static_cast<uint32_t>(i * 13 % 200), 0, 0, 1, 0});
    map.primary_weight.push_back(128);
  }
  map.gain_samples = choose_overlap_samples(map);
  return map;
}

std::vector<cv::Mat> flat_images(double a, double b) {
  return {cv::Mat(16, 16, CV_8UC1, cv::Scalar(a)), cv::Mat(16, 16, CV_8UC1, cv::Scalar(b))};
}

TEST(GainCompensator, FollowsAnExposureStepSmoothly) {
  const FusionMap map = overlapping_map();
  EXPECT_EQ(map.gain_samples.size(), 16u);
  GainCompensator compensator;
  const auto ratio = [&](const CameraGains& g) { return g.at(1, 0) / g.at(0, 0); };
  EXPECT_NEAR(ratio(compensator.update(map, flat_images(100, 100), 1)), 1, 1e-3);
  // Camera b's exposure jumps by 1.5: the gains move a fifth of the way (log domain) per frame.
  const double target = ratio(solve_gains(measure_overlaps(map, flat_images(100, 150), 1)));
  EXPECT_NEAR(target, 100.0 / 150, 0.02);
  const double first = ratio(compensator.update(map, flat_images(100, 150), 1));
  EXPECT_NEAR(std::log(first), GainCompensator::kSmoothing * std::log(target), 1e-3);
  for (int i = 0; i < 30; ++i) compensator.update(map, flat_images(100, 150), 1);
  EXPECT_NEAR(ratio(compensator.gains()), target, 1e-3);
}

TEST(GainCompensator, MapsWithoutOverlapSamplesGiveNoGains) {
  FusionMap map = overlapping_map();
  map.gain_samples.clear();
  GainCompensator compensator;
  EXPECT_TRUE(compensator.update(map, flat_images(100, 150), 1).empty());
}

TEST(GainCompensator, SaturatedAndBlackSamplesAreLeftOut) {
  const FusionMap map = overlapping_map();
  const OverlapStats s = measure_overlaps(map, flat_images(255, 100), 1);
  EXPECT_EQ(s.count[s.index(0, 0, 1)], 0);
  for (float g : solve_gains(s).gain) EXPECT_FLOAT_EQ(g, 1);
}

TEST(ApplyMapGains, ScaleEachCamerasSamplesBeforeBlending) {
  const FusionMap map = overlapping_map();
  CameraGains gains{1, {1.5f, 0.5f}};
  cv::Mat out;
  apply_map(map, flat_images(100, 200), out, 1, gains);
  // 150 and 100 blended 128/256 each.
  for (int i = 0; i < 16; ++i) EXPECT_EQ(out.data[i], 125);
  // Colour output from grey cameras: a gain per channel.
  CameraGains colour{3, {1, 2, 3, 1, 1, 1}};
  FusionMap primary_only = map;
  primary_only.secondary.clear();
  primary_only.primary_weight.clear();
  apply_map(primary_only, flat_images(60, 0), out, 3, colour);
  EXPECT_EQ(out.at<cv::Vec3b>(0, 0), cv::Vec3b(60, 120, 180));
  apply_map(primary_only, flat_images(100, 0), out, 3, colour);
  EXPECT_EQ(out.at<cv::Vec3b>(0, 0), cv::Vec3b(100, 200, 255));  // saturates
}

TEST(ApplyMapGains, BadGainsAndImagesGiveClearErrors) {
  const FusionMap map = overlapping_map();
  cv::Mat out;
  EXPECT_THROW(apply_map(map, flat_images(1, 1), out, 1, CameraGains{1, {1.0f}}), std::invalid_argument);
  EXPECT_THROW(apply_map(map, flat_images(1, 1), out, 3, CameraGains{1, {1.0f, 1.0f}}), std::invalid_argument);
  GainCompensator compensator;
  EXPECT_THROW(compensator.update(map, {cv::Mat(16, 16, CV_8UC1), cv::Mat(8, 8, CV_8UC1)}, 1), std::invalid_argument);
  EXPECT_THROW(compensator.update(map, {cv::Mat(16, 16, CV_8UC1)}, 1), std::invalid_argument);
  EXPECT_THROW(compensator.update(map, flat_images(1, 1), 2), std::invalid_argument);
}

}  // namespace
}  // namespace omniview
