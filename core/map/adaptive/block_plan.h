// Whether an output block may be interpolated from exact samples on a lattice, and the
// patches (patch.h) that then cover it.
#pragma once

#include <cstdint>
#include <vector>

#include "core/map/adaptive/patch.h"
#include "core/map/map_kernels.h"

namespace omniview::map_internal {

// The largest gap allowed between an interpolated source coordinate and the exact one.
inline constexpr float kTolerancePx = 0.05f;

// Exact winners on a lattice of N x N samples over a block, [row][column].
template <int N>
struct Lattice {
  int x[N], y[N];    // sample columns and rows, evenly spaced
  int x_end, y_end;  // the block's pixels: [x[0], x_end) x [y[0], y_end)
  float u[N][N], v[N][N];
  uint32_t cam[N][N];
  bool on_surface[N][N];
  // With occlusion only (Winners): the surface points and whether a better camera was hidden.
  float px[N][N], py[N][N], pz[N][N];
  uint8_t better_hidden[N][N];
  uint8_t shared[N][N];  // blend only: two or more cameras see the sample
};
using BlockLattice = Lattice<3>;  // corners, edge midpoints, centre
using FineLattice = Lattice<5>;   // a full 8x8 block every 2 pixels

enum class BlockPlan {
  kWhole,     // one bilinear patch: within kTolerancePx at every midpoint
  kQuarters,  // four bilinear patches cornered at the lattice: within 4 kTolerancePx (error ~ size^2)
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

// A block that curves too much for bilinear patches (a 360 deg fisheye view's outer rings)
// is usually smooth: one biquadratic patch through the 3x3 lattice at offsets 0, 4, 8,
// accepted where all 25 samples see the same camera and the 16 samples it does not pass
// through lie within the tolerance. Appends the patch and returns true, or returns false.
bool try_quadratic(const FineLattice& f, const std::vector<CameraSetup>& setups, std::vector<Patch>& patches);

// Quarter (qy, qx) of a fine lattice's block, as a block of its own.
BlockLattice quarter(const FineLattice& f, int qy, int qx);

}  // namespace omniview::map_internal
