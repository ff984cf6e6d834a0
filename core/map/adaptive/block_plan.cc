#include "core/map/adaptive/block_plan.h"

#include <algorithm>
#include <cmath>

namespace omniview::map_internal {
namespace {

// The patch between lattice points (column a..b, row p..q) over the given pixels.
Patch lattice_patch(const BlockLattice& s, int a, int b, int p, int q, int x_begin, int x_end, int y_begin,
                    int y_end) {
  return Patch{s.x[a], s.x[b], s.y[p], s.y[q],
               s.u[p][a], s.u[p][b], s.u[q][a], s.u[q][b],
               s.v[p][a], s.v[p][b], s.v[q][a], s.v[q][b],
               x_begin, x_end, y_begin, y_end, s.cam[0][0]};
}

// Largest gap between the whole-block interpolation and the exact midpoint samples (the
// corners are exact by construction). Bilinear error peaks at the centre for smooth maps;
// the edge midpoints catch saddle-shaped maps whose error cancels there.
float midpoint_error(const BlockLattice& s) {
  float error = 0;
  for (int p = 0; p < 3; ++p) {
    for (int k = 0; k < 3; ++k) {
      if (p != 1 && k != 1) continue;
      const float tx = static_cast<float>(s.x[k] - s.x[0]) / static_cast<float>(s.x[2] - s.x[0]);
      const float ty = static_cast<float>(s.y[p] - s.y[0]) / static_cast<float>(s.y[2] - s.y[0]);
      const float ul = s.u[0][0] + (s.u[2][0] - s.u[0][0]) * ty, ur = s.u[0][2] + (s.u[2][2] - s.u[0][2]) * ty;
      const float vl = s.v[0][0] + (s.v[2][0] - s.v[0][0]) * ty, vr = s.v[0][2] + (s.v[2][2] - s.v[0][2]) * ty;
      error = std::max({error, std::abs(ul + (ur - ul) * tx - s.u[p][k]), std::abs(vl + (vr - vl) * tx - s.v[p][k])});
    }
  }
  return error;
}

// Does the camera's mask allow every pixel the patch interpolates (as written)?
bool mask_allows_patch(const Camera& camera, const Patch& patch) {
  float u[kBlock + 1], v[kBlock + 1];
  uint32_t cams[kBlock + 1];
  for (int y = patch.y_begin; y < patch.y_end; ++y) {
    patch.fill_row(y, u, v, cams, patch.x_begin);
    for (int x = 0; x < patch.x_end - patch.x_begin; ++x) {
      if (!mask_allows(camera, u[x], v[x])) return false;
    }
  }
  return true;
}

}  // namespace

BlockPlan plan_block(const BlockLattice& s, const std::vector<CameraSetup>& setups, Quarters quarters,
                     std::vector<Patch>& patches) {
  const uint32_t cam = s.cam[0][0];
  bool same = cam != kNoCamera, off_surface = true;
  for (int p = 0; p < 3; ++p) {
    for (int k = 0; k < 3; ++k) same = same && s.cam[p][k] == cam, off_surface = off_surface && !s.on_surface[p][k];
  }
  if (!same) return off_surface ? BlockPlan::kBlack : BlockPlan::kExact;
  const float error = midpoint_error(s);
  const size_t first = patches.size();
  BlockPlan plan;
  if (error <= kTolerancePx) {
    plan = BlockPlan::kWhole;
    patches.push_back(lattice_patch(s, 0, 2, 0, 2, s.x[0], s.x_end, s.y[0], s.y_end));
  } else if (quarters == Quarters::kAllowed && error <= 4 * kTolerancePx) {
    // Bilinear error shrinks with the square of the block size: a block within four times
    // the tolerance is within it when split into quarters at the exact midpoints.
    plan = BlockPlan::kQuarters;
    const int xm = s.x[1], ym = s.y[1];
    patches.push_back(lattice_patch(s, 0, 1, 0, 1, s.x[0], xm, s.y[0], ym));
    patches.push_back(lattice_patch(s, 1, 2, 0, 1, xm, s.x_end, s.y[0], ym));
    patches.push_back(lattice_patch(s, 0, 1, 1, 2, s.x[0], xm, ym, s.y_end));
    patches.push_back(lattice_patch(s, 1, 2, 1, 2, xm, s.x_end, ym, s.y_end));
  } else {
    return BlockPlan::kExact;
  }
  const Camera& camera = *setups[cam].camera;
  if (!camera.mask.empty()) {
    for (size_t i = first; i < patches.size(); ++i) {
      if (!mask_allows_patch(camera, patches[i])) {
        patches.resize(first);
        return BlockPlan::kExact;
      }
    }
  }
  return plan;
}

}  // namespace omniview::map_internal
