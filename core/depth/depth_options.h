// Knobs and counters of a measured-depth surface (measured_depth_view.h).
#pragma once

#include <cstddef>

namespace omniview {

struct DepthOptions {
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
};

struct DepthStats {
  size_t points = 0;           // given
  size_t non_finite = 0;       // NaN or infinite coordinates: skipped
  size_t outside_view = 0;     // behind the view or outside its image
  size_t splatted_pixels = 0;  // view pixels that received a sample (nearest wins)
  size_t filled_pixels = 0;    // empty pixels filled between two samples
  size_t see_through = 0;      // samples replaced by a nearer surface that covers them
  size_t measured_pixels = 0;  // pixels on measured depth (splatted or filled)
  size_t blended_pixels = 0;   // pixels in the band where measured depth fades to the fixed surface
};

}  // namespace omniview
