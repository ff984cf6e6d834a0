// Joins measured samples across the gaps between them (a lidar's rings, missing returns):
// an empty pixel between two samples, left/right or up/down within DepthOptions::max_gap_deg,
// takes the surface through them when they lie on one surface (max_step_*): where its ray
// meets the straight segment between the two, exact for a surface flat between them. A sample that such a
// nearer surface covers from both sides was seen through it (the lidar saw past the
// object's edge between two of the view's rays) and gives way to it. Where both directions
// offer a surface the nearer one wins, as in a z-buffer. Two passes, so that rings joined
// along themselves are then joined to each other (gap_fill.cc).
#pragma once

#include <cstdint>
#include <vector>

#include "core/depth/depth_options.h"
#include "core/depth/view_rays.h"

namespace omniview {

// `range`: per pixel, 0 for none (splat_points). Returns the filled ranges; counts
// filled_pixels and see_through. `fillable` (optional, per pixel): only pixels marked 1 are
// filled or replaced, the rest stay as they are (and still serve as samples).
std::vector<float> fill_gaps(const ViewRays& rays, const std::vector<float>& range, const DepthOptions& options,
                             DepthStats& stats, const std::vector<uint8_t>* fillable = nullptr);

}  // namespace omniview
