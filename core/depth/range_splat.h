// Measured points into a view's pixels: each point goes to the pixel its ray passes
// through, and the nearest point per pixel wins (a z-buffer), so a surface's back side or
// what stands behind it never shows through a nearer sample of the same pixel.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/depth/depth_options.h"
#include "core/depth/view_rays.h"
#include "core/geometry/pose.h"

namespace omniview {

// Range per view pixel (row-major), 0 where no point fell. `points` are in some frame P and
// T_view_points places P in the view frame. Non-finite points are skipped and counted, as
// are points behind the view or outside its image (stats: points, non_finite,
// outside_view, splatted_pixels).
std::vector<float> splat_points(const ViewRays& rays, const std::vector<Eigen::Vector3f>& points,
                                const Pose& T_view_points, DepthStats& stats);

}  // namespace omniview
