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

// The same for points that each stand for a vertical stretch of surface `stretch_m` tall,
// from the point down (`up`: the vertical in the points' frame): every pixel the stretch
// crosses takes its range. Down, so that a point on a flat top (flat_tops.h) reaches into
// its object, never above its top. Columns of such points (column_completion.h) lie a few pixels
// apart both ways and off the view's rows and columns, where a gap fill that joins
// samples along rows and columns (gap_fill.h) left holes between them (golden front view:
// a crate's face below the lidar's rings in rectangles of the fixed surface); as stretches
// each column is a line from top to foot in any view, and the fill joins the lines.
std::vector<float> splat_stretches(const ViewRays& rays, const std::vector<Eigen::Vector3f>& points,
                                   const Pose& T_view_points, const Eigen::Vector3f& up, float stretch_m,
                                   DepthStats& stats);

}  // namespace omniview
