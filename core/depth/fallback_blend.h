// The surface a measured-depth view stands on: measured range where there is some, the
// view's fixed surface elsewhere, and between them a band (DepthOptions::blend_band_deg)
// outward from the measured pixels where the nearest measured range fades into the fixed
// one, in inverse range, so no step shows where the two meet. Only where the measured
// surface lies at or behind the fixed one: an object in front of it keeps its edge.
#pragma once

#include <vector>

#include "core/depth/depth_options.h"
#include "core/depth/view_rays.h"

namespace omniview {

struct BlendedSurface {
  std::vector<float> range;           // per pixel along its ray; 0: no surface point
  std::vector<uint8_t> measured;      // share of measured depth, 0..255 (255: measured)
  size_t measured_pixels = 0, blended_pixels = 0;
};

// `measured`: per pixel range, 0 for none (fill_gaps).
BlendedSurface blend_with_fixed(const ViewRays& rays, const std::vector<float>& measured, const DepthOptions& options);

}  // namespace omniview
