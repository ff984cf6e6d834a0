#include "core/map/adaptive/block_plan.h"

#include <algorithm>
#include <cmath>

namespace omniview::map_internal {
namespace {

// Appends the bilinear patch between lattice points (column a..b, row p..q) over the
// given pixels. Built in place: a patch assembled on the stack and copied in cost more
// than planning the block (store-forwarding stalls).
inline void add_lattice_patch(const BlockLattice& s, int a, int b, int p, int q, int x_begin, int x_end, int y_begin,
                              int y_end, std::vector<Patch>& patches) {
  Patch& patch = patches.emplace_back(s.x[a], s.x[b], s.y[p], s.y[q], x_begin, x_end, y_begin, y_end, s.cam[0][0],
                                      false);
  patch.u[0][0] = s.u[p][a], patch.u[0][2] = s.u[p][b], patch.u[2][0] = s.u[q][a], patch.u[2][2] = s.u[q][b];
  patch.v[0][0] = s.v[p][a], patch.v[0][2] = s.v[p][b], patch.v[2][0] = s.v[q][a], patch.v[2][2] = s.v[q][b];
  patch.finish();
}

// Largest gap between the whole-block interpolation and the exact midpoint samples (the
// corners are exact by construction). Bilinear error peaks at the centre for smooth maps;
// the edge midpoints catch saddle-shaped maps whose error cancels there.
float midpoint_error(const BlockLattice& s) {
  // Positions of the lattice lines within the block, 0 .. 1 (one division per axis).
  const float mid_x = static_cast<float>(s.x[1] - s.x[0]) / static_cast<float>(s.x[2] - s.x[0]);
  const float mid_y = static_cast<float>(s.y[1] - s.y[0]) / static_cast<float>(s.y[2] - s.y[0]);
  const float at_x[3] = {0.0f, mid_x, 1.0f}, at_y[3] = {0.0f, mid_y, 1.0f};
  float error = 0;
  for (int p = 0; p < 3; ++p) {
    for (int k = 0; k < 3; ++k) {
      if (p != 1 && k != 1) continue;
      const float tx = at_x[k], ty = at_y[p];
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
  for (int y = patch.y_begin; y < patch.y_end; ++y) {
    patch.fill_row(y, u, v, patch.x_begin);
    for (int x = 0; x < patch.x_end - patch.x_begin; ++x) {
      if (!mask_allows(camera, u[x], v[x])) return false;
    }
  }
  return true;
}

// Keeps patches [first, end) if the camera's mask allows them all; else drops them.
bool keep_if_unmasked(const Camera& camera, size_t first, std::vector<Patch>& patches) {
  if (camera.mask.empty()) return true;
  for (size_t i = first; i < patches.size(); ++i) {
    if (!mask_allows_patch(camera, patches[i])) {
      patches.erase(patches.begin() + static_cast<std::ptrdiff_t>(first), patches.end());
      return false;
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
    add_lattice_patch(s, 0, 2, 0, 2, s.x[0], s.x_end, s.y[0], s.y_end, patches);
  } else if (quarters == Quarters::kAllowed && error <= 4 * kTolerancePx) {
    plan = BlockPlan::kQuarters;
    const int xm = s.x[1], ym = s.y[1];
    add_lattice_patch(s, 0, 1, 0, 1, s.x[0], xm, s.y[0], ym, patches);
    add_lattice_patch(s, 1, 2, 0, 1, xm, s.x_end, s.y[0], ym, patches);
    add_lattice_patch(s, 0, 1, 1, 2, s.x[0], xm, ym, s.y_end, patches);
    add_lattice_patch(s, 1, 2, 1, 2, xm, s.x_end, ym, s.y_end, patches);
  } else {
    return BlockPlan::kExact;
  }
  return keep_if_unmasked(*setups[cam].camera, first, patches) ? plan : BlockPlan::kExact;
}

bool try_quadratic(const FineLattice& f, const std::vector<CameraSetup>& setups, std::vector<Patch>& patches) {
  const uint32_t cam = f.cam[0][0];
  if (cam == kNoCamera) return false;
  for (int p = 0; p < 5; ++p) {
    for (int k = 0; k < 5; ++k) {
      if (f.cam[p][k] != cam) return false;
    }
  }
  Patch& patch = patches.emplace_back(f.x[0], f.x[4], f.y[0], f.y[4], f.x[0], f.x_end, f.y[0], f.y_end, cam, true);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) patch.u[r][c] = f.u[2 * r][2 * c], patch.v[r][c] = f.v[2 * r][2 * c];
  }
  patch.finish();
  // The samples it does not pass through sit at a quarter of the block from its lattice
  // lines, where a cubic error (the leading term past a quadratic) reaches 0.974 of its
  // peak (at 0.211): measured against 0.97 of the tolerance, the peak is within it.
  constexpr float kQuadraticTolerancePx = 0.97f * kTolerancePx;
  for (int p = 0; p < 5; ++p) {
    const Patch::Row row = patch.row(f.y[p]);
    for (int k = p % 2 ? 0 : 1; k < 5; k += p % 2 ? 1 : 2) {
      const float t = static_cast<float>(f.x[k] - f.x[0]);
      const float u = row.ua + t * (row.ub + t * row.uc), v = row.va + t * (row.vb + t * row.vc);
      if (!(std::abs(u - f.u[p][k]) <= kQuadraticTolerancePx && std::abs(v - f.v[p][k]) <= kQuadraticTolerancePx)) {
        patches.pop_back();
        return false;
      }
    }
  }
  return keep_if_unmasked(*setups[cam].camera, patches.size() - 1, patches);
}

BlockLattice quarter(const FineLattice& f, int qy, int qx) {
  BlockLattice b;
  for (int i = 0; i < 3; ++i) b.x[i] = f.x[2 * qx + i], b.y[i] = f.y[2 * qy + i];
  b.x_end = qx ? f.x_end : b.x[2];
  b.y_end = qy ? f.y_end : b.y[2];
  for (int p = 0; p < 3; ++p) {
    for (int k = 0; k < 3; ++k) {
      const int fp = 2 * qy + p, fk = 2 * qx + k;
      b.u[p][k] = f.u[fp][fk], b.v[p][k] = f.v[fp][fk], b.cam[p][k] = f.cam[fp][fk];
      b.on_surface[p][k] = f.on_surface[fp][fk];
      b.px[p][k] = f.px[fp][fk], b.py[p][k] = f.py[fp][fk], b.pz[p][k] = f.pz[fp][fk];
      b.better_hidden[p][k] = f.better_hidden[fp][fk];
      b.shared[p][k] = f.shared[fp][fk];
    }
  }
  return b;
}

}  // namespace omniview::map_internal
