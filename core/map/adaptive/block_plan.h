// Whether an output block may be interpolated from exact samples on a 3x3 lattice
// (corners, edge midpoints, centre), and the bilinear patches that then cover it.
#pragma once

#include <cstdint>
#include <vector>

#include "core/map/map_kernels.h"

namespace omniview::map_internal {

// The largest gap allowed between an interpolated source coordinate and the exact one.
inline constexpr float kTolerancePx = 0.05f;

// A block's exact winners on its lattice, [row][column].
struct BlockLattice {
  int x[3], y[3];    // lattice columns and rows; x[1], y[1] are the midpoints
  int x_end, y_end;  // the block's pixels: [x[0], x_end) x [y[0], y_end)
  float u[3][3], v[3][3];
  uint32_t cam[3][3];
  bool on_surface[3][3];
};

// Source coordinates bilinear over output pixels [x_begin, x_end) x [y_begin, y_end),
// from exact values at the corners (x0, y0) ... (x1, y1).
struct Patch {
  int x0, x1, y0, y1;
  float u00, u10, u01, u11, v00, v10, v01, v11;  // uXY: X = 0 left / 1 right, Y = 0 top / 1 bottom
  int x_begin, x_end, y_begin, y_end;
  uint32_t cam;

  // Row y's pixels into u, v, cams, at index (output column - origin).
  void fill_row(int y, float* __restrict u, float* __restrict v, uint32_t* __restrict cams, int origin = 0) const {
    const float inv_w = 1.0f / static_cast<float>(x1 - x0), inv_h = 1.0f / static_cast<float>(y1 - y0);
    const float ty = static_cast<float>(y - y0) * inv_h;
    const float ul = u00 + (u01 - u00) * ty, ur = u10 + (u11 - u10) * ty;
    const float vl = v00 + (v01 - v00) * ty, vr = v10 + (v11 - v10) * ty;
    const float du = (ur - ul) * inv_w, dv = (vr - vl) * inv_w;
    for (int x = x_begin; x < x_end; ++x) {
      const float t = static_cast<float>(x - x0);
      u[x - origin] = ul + du * t;
      v[x - origin] = vl + dv * t;
      cams[x - origin] = cam;
    }
  }
};

enum class BlockPlan {
  kWhole,     // one patch: interpolation within kTolerancePx at every midpoint
  kQuarters,  // four patches cornered at the lattice: within 4 kTolerancePx (error ~ size^2)
  kBlack,     // off the view's surface at all nine samples (a fisheye view's corners)
  kExact,     // anything else: seams, coverage edges, masks, strong curvature
};

// kQuarters rests on the error shrinking with the square of the block size, which holds
// for 8x8 blocks of smooth maps; the 4x4 blocks of a split block, where curvature is
// strong, must meet the tolerance as measured (quarters there measured 0.06 px off).
enum class Quarters { kAllowed, kNotAllowed };

// Plans the block; for kWhole and kQuarters appends its patches to `patches`. Every
// interpolated pixel must lie where its camera's mask (if any) allows it.
BlockPlan plan_block(const BlockLattice& b, const std::vector<CameraSetup>& setups, Quarters quarters,
                     std::vector<Patch>& patches);

}  // namespace omniview::map_internal
