// Per-camera intensity gains that even out the cameras' exposures where a view blends them
// (Brown & Lowe, "Automatic Panoramic Image Stitching using Invariant Features", IJCV 2007,
// section 6). Estimated by gain_estimate.h, smoothed over frames by gain_compensator.h and
// applied by apply_map (core/map/apply.h).
#pragma once

#include <cstddef>
#include <vector>

namespace omniview {

struct CameraGains {
  int channels = 0;         // of the output the gains were measured in (1 or 3)
  std::vector<float> gain;  // gain[camera * channels + channel]; empty: no compensation

  bool empty() const { return gain.empty(); }
  size_t cameras() const { return channels > 0 ? gain.size() / static_cast<size_t>(channels) : 0; }
  float at(size_t camera, int channel) const { return gain[camera * static_cast<size_t>(channels) + channel]; }
};

}  // namespace omniview
