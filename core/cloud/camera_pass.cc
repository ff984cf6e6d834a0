// One camera's pass over the cloud: projection into its image and the depth buffer that
// says which points a nearer surface hides (see CloudColourer in colourer.h).
#include <cmath>
#include <limits>

#include "core/cloud/colourer_internal.h"
#include "core/map/multiversion.h"

namespace omniview::cloud_internal {

namespace {

constexpr float kFarDepth = std::numeric_limits<float>::max();

// dst = min(dst, src), elementwise; a loop of its own so that it vectorises.
void min_into(float* __restrict dst, const float* __restrict src, int n) {
  for (int x = 0; x < n; ++x) dst[x] = src[x] < dst[x] ? src[x] : dst[x];
}

// Projects every point with one camera's model: the variant is visited once, and this
// loop is specialised per model, so the projection inlines and GCC vectorises it.
template <typename Model>
[[gnu::always_inline]] inline void project_all(const Model& model, const Eigen::Matrix<float, 3, 4>& T,
                                               const float* __restrict x, const float* __restrict y,
                                               const float* __restrict z, size_t n, float max_u, float max_v,
                                               float* __restrict u, float* __restrict v, float* __restrict range,
                                               uint8_t* __restrict ok) {
  const float r00 = T(0, 0), r01 = T(0, 1), r02 = T(0, 2), t0 = T(0, 3);
  const float r10 = T(1, 0), r11 = T(1, 1), r12 = T(1, 2), t1 = T(1, 3);
  const float r20 = T(2, 0), r21 = T(2, 1), r22 = T(2, 2), t2 = T(2, 3);
  for (size_t i = 0; i < n; ++i) {
    const float xc = r00 * x[i] + r01 * y[i] + r02 * z[i] + t0;
    const float yc = r10 * x[i] + r11 * y[i] + r12 * z[i] + t1;
    const float zc = r20 * x[i] + r21 * y[i] + r22 * z[i] + t2;
    float uu, vv;
    const bool good = model.project(xc, yc, zc, uu, vv);
    u[i] = uu;
    v[i] = vv;
    range[i] = std::sqrt(xc * xc + yc * yc + zc * zc);
    // Bit 1: the model images it (for the depth buffer, which reaches past the image's
    // edges); bit 0: also inside the image. NaN coordinates fail every comparison, so
    // points without a return drop out here.
    const bool inside = good & (uu >= 0.f) & (vv >= 0.f) & (uu <= max_u) & (vv <= max_v);
    ok[i] = static_cast<uint8_t>((static_cast<uint8_t>(good) << 1) | static_cast<uint8_t>(inside));
  }
}

}  // namespace

// Compiled for baseline x86-64 and for AVX2 (picked at load).
OMNIVIEW_MULTIVERSION
void project_camera(const CameraModel& camera_model, const Eigen::Matrix<float, 3, 4>& T, const float* x,
                    const float* y, const float* z, size_t n, float max_u, float max_v, float* u, float* v,
                    float* range, uint8_t* ok) {
  // get_if rather than std::visit: the loop must inline into each clone of this function.
  auto run = [&](const auto* model) {
    if (model) project_all(*model, T, x, y, z, n, max_u, max_v, u, v, range, ok);
  };
  run(std::get_if<PinholeRadtan>(&camera_model));
  run(std::get_if<Equidistant>(&camera_model));
  run(std::get_if<Fov>(&camera_model));
  run(std::get_if<OmniRadtan>(&camera_model));
  run(std::get_if<DoubleSphere>(&camera_model));
  run(std::get_if<Eucm>(&camera_model));
}

// Two loops: cell indices, branch-free so they vectorise (a point the buffer does not
// reach goes to the spare last cell), then the scatter, one load and store per point.
// The scatter skips the spare cell by a branch: points outside a camera come in long runs,
// so it predicts well, where a store to the same cell every time would wait on the last.
void splat(const CameraPass& pass, const float* u, const float* v, const float* range, const uint8_t* valid,
           size_t n, float* depth) {
  constexpr size_t kBlock = 512;
  int32_t cell[kBlock];
  const float cols = static_cast<float>(pass.cols), rows = static_cast<float>(pass.rows);
  const int pcols = pass.padded_cols(), pad = pass.reach;
  const int spare = static_cast<int>(pass.padded_size() - 1);
  for (size_t b = 0; b < n; b += kBlock) {
    const size_t m = std::min(kBlock, n - b);
    for (size_t i = 0; i < m; ++i) {
      const float cx = u[b + i] * pass.inv_cell + pass.offset, cy = v[b + i] * pass.inv_cell + pass.offset;
      const bool in = (valid[b + i] != 0) & (cx >= 0.f) & (cy >= 0.f) & (cx < cols) & (cy < rows);
      const float sx = in ? cx : 0.f, sy = in ? cy : 0.f;  // no NaN into the conversions
      const int at = (static_cast<int>(sy) + pad) * pcols + static_cast<int>(sx) + pad;
      cell[i] = in ? at : spare;
    }
    for (size_t i = 0; i < m; ++i) {
      if (cell[i] == spare) continue;
      float& d = depth[cell[i]];
      d = std::min(d, range[b + i]);
    }
  }
}

// The depth of a surface in front of each cell, from the cloud's own points splatted into
// the depth buffer (nearest per cell): a cell is covered when nearer samples lie on both
// sides of it within `reach` cells, vertically or horizontally (the gap between two of a
// lidar's rings on a near surface). Requiring both sides, and leaving the cell itself out,
// keeps a surface seen at a grazing angle from hiding itself: there the nearer ring lies on
// one side only, or shares the cell. Row by row, with the buffer's far border standing for
// what lies past it; the minima over each side are exact, so the order does not matter.
void occluding_depth(CameraPass& pass) {
  const int rows = pass.rows, cols = pass.cols, pcols = pass.padded_cols(), reach = pass.reach;
  const float* depth = pass.depth[0].data();
  pass.occluder.resize(size_t(rows) * size_t(cols));
  std::vector<float> sides(4 * size_t(cols));
  float* up = sides.data();
  float* down = up + cols;
  float* left = down + cols;
  float* right = left + cols;
  for (int y = 0; y < rows; ++y) {
    const float* centre = depth + ptrdiff_t(y + reach) * pcols + reach;
    std::fill(sides.begin(), sides.end(), kFarDepth);
    for (int k = 1; k <= reach; ++k) {
      min_into(up, centre - ptrdiff_t(k) * pcols, cols);
      min_into(down, centre + ptrdiff_t(k) * pcols, cols);
      min_into(left, centre - k, cols);
      min_into(right, centre + k, cols);
    }
    float* out = pass.occluder.data() + ptrdiff_t(y) * cols;
    for (int x = 0; x < cols; ++x) out[x] = std::min(std::max(up[x], down[x]), std::max(left[x], right[x]));
  }
}

}  // namespace omniview::cloud_internal
