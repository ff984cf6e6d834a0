// One view's gain compensation over time: estimates gains from each image set and smooths
// them, so that exposure changes (slow on real cameras) are followed without flicker.
// Not thread-safe: one per view, used by the thread that renders it.
#pragma once

#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/gain/camera_gains.h"
#include "core/gain/gain_estimate.h"
#include "core/map/fusion_map.h"

namespace omniview {

class GainCompensator {
 public:
  // Share of a new estimate in the smoothed gains per image set, taken in the log domain
  // (a gain of 0.5 and one of 2 are equally far from 1). 0.2 follows a step in exposure
  // to 90 % within 10 image sets (2/3 s at 15 Hz) and scales the estimate's
  // frame-to-frame noise down five-fold.
  static constexpr double kSmoothing = 0.2;

  explicit GainCompensator(GainPrior prior = {}) : prior_(prior) {}

  // Measures `images` (as for apply_map; bad ones throw std::invalid_argument) over the map's
  // overlap samples and returns the smoothed gains to pass to apply_map. A map without
  // overlap samples (nearest fusion, compensation off, no overlap) gives empty gains. The
  // first image set, or one after a change of camera count or channels, starts afresh.
  const CameraGains& update(const FusionMap& map, const std::vector<cv::Mat>& images, int channels);

  const CameraGains& gains() const { return gains_; }
  void reset() { gains_ = {}; }

 private:
  GainPrior prior_;
  CameraGains gains_;
};

}  // namespace omniview
