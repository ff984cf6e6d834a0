// Knobs and counters of a measured-depth surface (measured_depth_view.h).
#pragma once

#include <cstddef>

namespace omniview {

struct DepthOptions {
  // The surface is built on a lattice of cells about this wide (surface_lattice.h), never
  // finer than the view's pixels, where the points are sparser than the view's pixels
  // (DepthSurface::kDenseSamplesPerPixel). The samples that make a surface are far coarser:
  // Spot's depth images as the daemon takes them ~1.1 deg apart, a VLP-16's rings 2 deg
  // apart (0.1-0.4 deg along a ring; the nearest of a cell's samples wins). A quarter of a
  // degree places an object's edge to 1.3 cm at 3 m. Measured on the golden front view at
  // 1024 x 512 (2 x 2 pixels a cell) against its own pixels: one rotation 43.7 vs 42.3 dB,
  // depth images 46.4 vs 46.3; 3 x 3 pixels a cell (0.35 deg) lost 2.8 dB there (a corner
  // where the view sees an object the lidar saw over became judged and black); the bird's-
  // eye at 1200 x 1200 (2 x 2) 31.3 vs 31.7 dB on one rotation.
  double lattice_cell_deg = 0.25;
  // Gap filling between measured samples (gap_fill.h). Two samples on either side of an
  // empty pixel (left/right or up/down in the view) are joined when they are at most
  // `max_gap_deg` apart as the view sees them and at most max_step_rel * range + max_step_m
  // apart in space. A VLP-16's rings are 2 deg apart: on a surface facing the lidar that is
  // 3.5 % of the range (10 cm at 3 m), 7 % at 60 deg incidence, so 10 % joins the rings of
  // any surface up to ~70 deg incidence, while a step of more than a tenth of the range (a
  // pillar before a wall, a box's edge) stays a step. 5 deg, 2.5 rings, leaves room for a
  // view whose centre is off the lidar's (its rings look farther apart) and for one missing
  // return. A floor seen at a grazing angle is not joined: there the view's fixed surface
  // (the ground, with `ground: true` or a bird's-eye view) is the better guess anyway.
  double max_gap_deg = 5.0;
  double max_step_rel = 0.10;
  double max_step_m = 0.05;
  // Where nothing was measured the fixed surface takes over, blended over this band (in the
  // view, outward from the measured pixels) in inverse range, so seams, whose parallax
  // between cameras is linear in 1 / range, move evenly across it instead of jumping. One
  // VLP-16 ring spacing: the fade spans what the lidar leaves between two rings at the edge
  // of its field. (Wider fades cost the golden bird's-eye view: 3 deg 31.0 dB, 2 deg 31.6,
  // 1 deg 32.1 without occlusion; a narrower one is closer to a step.)
  double blend_band_deg = 2.0;
  // The completing points (column_completion.h) stand this far apart up their columns
  // (ColumnOptions::step_m): each is splatted as a vertical stretch this tall down from it
  // (splat_stretches), the points' frame's z up.
  float completion_stretch_m = 0.05f;
};

struct DepthStats {
  size_t points = 0;           // given
  size_t non_finite = 0;       // NaN or infinite coordinates: skipped
  size_t outside_view = 0;     // behind the view or outside its image
  // Of the lattice's cells (the view's pixels where the lattice is the view's own):
  size_t splatted_pixels = 0;  // cells that received a sample (nearest wins)
  size_t filled_pixels = 0;    // empty cells filled between two samples
  size_t see_through = 0;      // samples replaced by a nearer surface that covers them
  size_t completed_pixels = 0; // empty cells given a completing point (column_completion.h)
  // Of the view's pixels:
  size_t measured_pixels = 0;  // pixels on measured depth (splatted or filled)
  size_t blended_pixels = 0;   // pixels in the band where measured depth fades to the fixed surface
};

}  // namespace omniview
