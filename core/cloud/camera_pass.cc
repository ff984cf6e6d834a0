// One camera's pass over the cloud: projection into its image and the depth buffer that
// says which points a nearer surface hides (see CloudColourer in colourer.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/cloud/colourer_internal.h"
#include "core/map/multiversion.h"

namespace omniview::cloud_internal {

namespace {

// w[i] = min(src[i], src[i + stride], ..., src[i + (width - 1) stride]) for every i whose
// window lies in [0, size): by doubling windows, a few passes over the buffer whatever the
// width. `tmp` holds as much as `w`.
void window_min(const float* src, size_t size, size_t stride, int width, float* w, float* tmp) {
  const float* cur = src;
  int have = 1;  // cur[i] is the minimum over `have` samples from i
  while (have * 2 <= width) {
    const size_t step = size_t(have) * stride, valid = size - std::min(size, (2 * size_t(have) - 1) * stride);
    float* __restrict out = (cur == tmp) ? w : tmp;
    const float* __restrict a = cur;
    for (size_t i = 0; i < valid; ++i) out[i] = a[i + step] < a[i] ? a[i + step] : a[i];
    cur = out;
    have *= 2;
  }
  const size_t step = size_t(width - have) * stride, valid = size - std::min(size, (size_t(width) - 1) * stride);
  if (cur == w) {  // finish in place: each w[i] reads w[i] and a later w[i + step]
    for (size_t i = 0; i < valid; ++i) w[i] = w[i + step] < w[i] ? w[i + step] : w[i];
  } else {
    float* __restrict out = w;
    const float* __restrict a = cur;
    for (size_t i = 0; i < valid; ++i) out[i] = a[i + step] < a[i] ? a[i + step] : a[i];
  }
}

// How far a surface's depth changes across one cell, along one axis, from the nearest samples
// on either side of a cell within the reach (`a`, `b`): on a surface seen at a slant, the
// nearer side's nearest sample lies `reach` cells away, the farther side's next to the cell.
// Empty sides (no sample within the reach) say nothing.
[[gnu::always_inline]] inline float change_per_cell(float a, float b, float per_cell) {
  constexpr float kEmpty = std::numeric_limits<float>::max();
  return a < kEmpty && b < kEmpty ? std::abs(a - b) * per_cell : 0.f;
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

double pixels_per_radian(const Camera& cam) {
  const double cx = (cam.width - 1) / 2.0, cy = (cam.height - 1) / 2.0;
  Eigen::Vector3d a, b;
  if (unproject(cam.model, Eigen::Vector2d(static_cast<float>(cx), static_cast<float>(cy)), a) &&
      unproject(cam.model, Eigen::Vector2d(static_cast<float>(cx) + 1, static_cast<float>(cy)), b)) {
    const double angle = std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
    if (angle > 0) return 1.0 / angle;
    return 1;
  }
  return cam.width / M_PI;
}

void size_depth_buffer(CameraPass& pass, const Camera& cam, double px_per_rad, double cell_deg, int reach) {
  const float cell = std::max(1.0f, float(px_per_rad * cell_deg * M_PI / 180));
  pass.inv_cell = 1.f / cell;
  pass.reach = reach;
  pass.offset = static_cast<float>(reach);
  pass.rows = static_cast<int>(cam.height * pass.inv_cell) + 1 + 2 * reach;
  pass.cols = static_cast<int>(cam.width * pass.inv_cell) + 1 + 2 * reach;
}

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

// One loop, branching on what a camera sees: points outside a camera come in long runs, so
// the branches predict well, and the stores then go only where they count.
void splat_and_keep(const CameraPass& pass, size_t first, const float* u, const float* v, const float* range,
                    const uint8_t* valid, size_t n, float* depth, Seen& seen) {
  const float cols = static_cast<float>(pass.cols), rows = static_cast<float>(pass.rows);
  const float inv_cell = pass.inv_cell, offset = pass.offset;
  const int pcols = pass.padded_cols(), pad = pass.reach;
  // Locals, not the Seen's members: stores through `seen` each point would also go to a
  // cache line that the next range's Seen, filled by another thread, shares.
  size_t kept = seen.size;
  uint32_t* __restrict index = seen.index.get();
  float* __restrict seen_u = seen.u.get();
  float* __restrict seen_v = seen.v.get();
  float* __restrict seen_range = seen.range.get();
  for (size_t i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    if (depth) {
      const float cx = u[i] * inv_cell + offset, cy = v[i] * inv_cell + offset;
      if (cx >= 0.f && cy >= 0.f && cx < cols && cy < rows) {
        float& d = depth[(static_cast<int>(cy) + pad) * pcols + static_cast<int>(cx) + pad];
        d = std::min(d, range[i]);
      }
    }
    if (valid[i] & 1) {
      index[kept] = static_cast<uint32_t>(first + i);
      seen_u[kept] = u[i];
      seen_v[kept] = v[i];
      seen_range[kept] = range[i];
      ++kept;
    }
  }
  seen.size = kept;
}

// The depth of a surface in front of each cell, from the cloud's own points splatted into
// the depth buffer (nearest per cell): a cell is covered when nearer samples lie on both
// sides of it within `reach` cells, vertically or horizontally (the gap between two of a
// lidar's rings on a near surface). Requiring both sides, and leaving the cell itself out,
// keeps a surface seen at a grazing angle from hiding itself: there the nearer ring lies on
// one side only, or shares the cell. Each pair's covering depth is then moved back by the
// surface's depth change across one cell along the other axis: the pair's cells span a whole
// cell across their axis, so where the surface's depth changes along it (a floor or a wall
// seen at a slant, with a camera's rows not along it) their nearest sample lies up to that
// much nearer than a point of the same surface in this cell. Without it that surface hides
// itself unless the tolerance is ~10 % of the range, which lets points 0.4 m behind a wall
// 4 m away through (ColourOptions::occlusion_tolerance_rel). Row by row, with the buffer's
// far border standing for what lies past it; the minima over each side are exact, so the
// order does not matter.
void occluding_depth(CameraPass& pass) {
  const int rows = pass.rows, cols = pass.cols, pcols = pass.padded_cols(), reach = pass.reach;
  const float* depth = pass.depth[0].data();
  const size_t size = pass.padded_size() - 1;  // the spare last cell is no part of the picture
  // Minima over `reach` cells down (vertical) and to the right (horizontal) from each cell.
  thread_local std::vector<float> vertical, horizontal, tmp;
  vertical.resize(size);
  horizontal.resize(size);
  tmp.resize(size);
  window_min(depth, size, size_t(pcols), reach, vertical.data(), tmp.data());
  window_min(depth, size, 1, reach, horizontal.data(), tmp.data());
  pass.occluder.resize(size_t(rows) * size_t(cols));
  const float per_cell = 1.f / float(reach);
  for (int y = 0; y < rows; ++y) {
    const ptrdiff_t p = ptrdiff_t(y + reach) * pcols + reach;  // cell (y, 0) in the padded buffer
    const float* __restrict up = vertical.data() + p - ptrdiff_t(reach) * pcols;  // rows y-reach .. y-1
    const float* __restrict down = vertical.data() + p + pcols;                   // rows y+1 .. y+reach
    const float* __restrict left = horizontal.data() + p - reach;                 // columns x-reach .. x-1
    const float* __restrict right = horizontal.data() + p + 1;                    // columns x+1 .. x+reach
    float* __restrict out = pass.occluder.data() + ptrdiff_t(y) * cols;
    for (int x = 0; x < cols; ++x) {
      const float vertical_change = change_per_cell(up[x], down[x], per_cell);
      const float horizontal_change = change_per_cell(left[x], right[x], per_cell);
      out[x] = std::min(std::max(up[x], down[x]) + horizontal_change, std::max(left[x], right[x]) + vertical_change);
    }
  }
}

}  // namespace omniview::cloud_internal
