// The lattice a measured surface is built on: the view's own projection at a coarser pixel
// (a cell of about DepthOptions::lattice_cell_deg), so the splat, the gap fill and the blend
// cost the same whatever the view's resolution, and join the same samples: a gap's reach
// and a ring's spacing are counted in cells of a fixed angle, not in the view's pixels. The
// surface is then read back at every view pixel (upsample_surface), on the view's own
// fixed surface where nothing was measured.
//
// Why: the measured points are far sparser than a big view's pixels (a VLP-16's rings 2 deg
// apart, 0.2 deg along a ring; Spot's depth images as the daemon takes them ~1 deg), so a
// surface per view pixel spent its time filling gaps between samples, and at 4096 x 2048 it
// left more unjoined than at 512 x 256 (a reviewer: 77 % vs 99 % of pixels on measured
// depth for the same points).
#pragma once

#include <memory>
#include <vector>

#include "core/depth/depth_options.h"
#include "core/depth/fallback_blend.h"
#include "core/depth/view_rays.h"

namespace omniview {

struct SurfaceLattice {
  std::shared_ptr<const ViewRays> cells;  // the lattice's rays: a view of the same type and field, fewer pixels
  int cell = 1;                           // view pixels per cell along each axis (1: the view's own pixels)
  // Each view column / row in lattice coordinates (cell centres at integers). The
  // projections of every view type are separable this way (checked when made).
  std::vector<float> column_at, row_at;
};

// The lattice of `view` for cells of about `cell_deg` (never finer than the view's pixels).
// Falls back to the view's own pixels (cell 1) for a view whose lattice would not line up.
SurfaceLattice make_surface_lattice(std::shared_ptr<const ViewRays> view, double cell_deg);

// The view's surface from the lattice's: at each view pixel, the measured range of the
// cells around it (bilinear where the four lie on one surface, within options.max_step_*;
// else the cell the pixel is in), in the blend band the cell's share of measured depth
// applied to the pixel's own fixed range, and the fixed surface elsewhere. `sampled`: per
// cell, 1 where a point gave its range. Counts measured and blended view pixels.
struct UpsampledSurface {
  std::vector<float> range;
  std::vector<uint8_t> measured, sampled;
  size_t measured_pixels = 0, blended_pixels = 0;
};
UpsampledSurface upsample_surface(const SurfaceLattice& lattice, const ViewRays& view, const BlendedSurface& cells,
                                  const std::vector<uint8_t>& sampled, const DepthOptions& options);

}  // namespace omniview
