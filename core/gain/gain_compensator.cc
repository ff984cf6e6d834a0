#include "core/gain/gain_compensator.h"

#include <cmath>

namespace omniview {

const CameraGains& GainCompensator::update(const FusionMap& map, const std::vector<cv::Mat>& images, int channels) {
  if (map.gain_samples.empty()) {
    // Keep nothing: a view switched back to compensation starts from its first estimate.
    gains_ = {};
    return gains_;
  }
  const CameraGains estimate = solve_gains(measure_overlaps(map, images, channels), prior_);
  if (gains_.channels != estimate.channels || gains_.gain.size() != estimate.gain.size()) {
    gains_ = estimate;
    return gains_;
  }
  for (size_t i = 0; i < gains_.gain.size(); ++i) {
    const double smoothed = (1 - kSmoothing) * std::log(gains_.gain[i]) + kSmoothing * std::log(estimate.gain[i]);
    gains_.gain[i] = static_cast<float>(std::exp(smoothed));
  }
  return gains_;
}

}  // namespace omniview
