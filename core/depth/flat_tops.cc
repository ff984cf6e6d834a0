#include "core/depth/flat_tops.h"

#include <algorithm>
#include <climits>
#include <cmath>

namespace omniview {

std::vector<Eigen::Vector3f> flat_top_points(const std::vector<Eigen::Vector3f>& points,
                                             const std::vector<CellTop>& tops, const Eigen::Vector2f& centre,
                                             const FlatTopOptions& options) {
  if (tops.empty() || !(options.cell_m > 0.f)) return {};
  const float cell = options.cell_m, inv_cell = 1.f / cell;
  const int reach = std::max(1, static_cast<int>(options.max_gap_m * inv_cell));
  const auto near_centre = [&](const CellTop& t) {
    const Eigen::Vector2f at((float(t.ix) + 0.5f) * cell, (float(t.iy) + 0.5f) * cell);
    return (at - centre).norm() <= options.max_range_m;
  };
  // A dense grid over the tops near the centre, `reach` cells around them.
  int x0 = INT_MAX, y0 = INT_MAX, x1 = INT_MIN, y1 = INT_MIN;
  for (const CellTop& t : tops) {
    if (!near_centre(t)) continue;
    x0 = std::min(x0, t.ix), x1 = std::max(x1, t.ix), y0 = std::min(y0, t.iy), y1 = std::max(y1, t.iy);
  }
  if (x0 > x1) return {};
  x0 -= reach, y0 -= reach, x1 += reach, y1 += reach;
  const int w = x1 - x0 + 1, h = y1 - y0 + 1;
  const auto index = [&](int ix, int iy) { return size_t(iy - y0) * size_t(w) + size_t(ix - x0); };
  const auto inside = [&](int ix, int iy) { return ix >= x0 && ix <= x1 && iy >= y0 && iy <= y1; };

  std::vector<uint8_t> occupied(size_t(w) * size_t(h), 0);
  for (const Eigen::Vector3f& p : points) {
    if (!p.allFinite()) continue;
    const float fx = std::floor(p.x() * inv_cell), fy = std::floor(p.y() * inv_cell);
    if (fx < float(x0) || fx > float(x1) || fy < float(y0) || fy > float(y1)) continue;
    occupied[index(static_cast<int>(fx), static_cast<int>(fy))] = 1;
  }
  std::vector<float> top(occupied.size(), NAN);
  for (const CellTop& t : tops) {
    if (!near_centre(t)) continue;
    top[index(t.ix, t.iy)] = t.z;
    occupied[index(t.ix, t.iy)] = 1;
  }

  // Walk from each top along four directions (the other four are the walks from the far
  // end); an empty cell joined from several takes the shortest join.
  std::vector<float> joined(occupied.size(), NAN);
  std::vector<float> span(occupied.size(), INFINITY);
  constexpr int kDirections[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  for (const CellTop& t : tops) {
    if (!near_centre(t)) continue;
    for (const auto& d : kDirections) {
      const float step = cell * std::hypot(float(d[0]), float(d[1]));
      for (int k = 1; float(k) * step <= options.max_gap_m + 1e-4f; ++k) {
        const int ix = t.ix + k * d[0], iy = t.iy + k * d[1];
        if (!inside(ix, iy)) break;
        const size_t far = index(ix, iy);
        if (!occupied[far]) continue;
        const float z_far = top[far];
        if (k > 1 && std::isfinite(z_far) && std::abs(z_far - t.z) <= options.max_step_m) {
          const float length = float(k) * step;
          for (int j = 1; j < k; ++j) {
            const size_t i = index(t.ix + j * d[0], t.iy + j * d[1]);
            if (length >= span[i]) continue;
            span[i] = length;
            joined[i] = t.z + (z_far - t.z) * float(j) / float(k);
          }
        }
        break;
      }
    }
  }
  std::vector<Eigen::Vector3f> out;
  for (int iy = y0; iy <= y1; ++iy) {
    for (int ix = x0; ix <= x1; ++ix) {
      const float z = joined[index(ix, iy)];
      if (std::isfinite(z)) out.emplace_back((float(ix) + 0.5f) * cell, (float(iy) + 0.5f) * cell, z);
    }
  }
  return out;
}

}  // namespace omniview
