#include "core/depth/gap_fill.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>

#include <opencv2/core/utility.hpp>

#include "core/map/occlusion.h"
#include "core/map/parallel_rows.h"

namespace omniview {
namespace {

// Distance in pixels to the nearest sample strictly before each pixel along a line (0:
// none within `reach`); `step` walks the line in memory.
inline void nearest_before(const float* range, size_t step, int count, int reach, uint16_t* out, size_t out_step) {
  int last = -reach - 1;
  for (int k = 0; k < count; ++k) {
    out[k * out_step] = static_cast<uint16_t>(k - last <= reach ? k - last : 0);
    if (range[k * step] > 0.f) last = k;
  }
}

inline void nearest_after(const float* range, size_t step, int count, int reach, uint16_t* out, size_t out_step) {
  int next = count + reach + 1;
  for (int k = count - 1; k >= 0; --k) {
    out[k * out_step] = static_cast<uint16_t>(next - k <= reach ? next - k : 0);
    if (range[k * step] > 0.f) next = k;
  }
}

// One pass: each empty pixel from the samples of `range` on either side of it.
std::vector<float> fill_once(const ViewRays& rays, const std::vector<float>& range, const DepthOptions& options,
                             DepthStats& stats, const std::vector<uint8_t>* fillable) {
  const int w = rays.width, h = rays.height;
  const int reach = std::clamp(static_cast<int>(std::ceil(options.max_gap_deg * M_PI / 180 / rays.pixel_rad)), 1,
                               std::min(30000, std::max(w, h)));
  const size_t n = rays.size();
  // Nearest samples left, right, up and down of each pixel.
  // Scratch kept per calling thread: fresh 4 MB every update was a tenth of its time in
  // page faults.
  // (Named through references: a lambda run on a worker thread that named the thread_local
  // itself would get that worker's own, empty, instance.)
  thread_local std::vector<uint16_t> scratch[4];
  std::vector<uint16_t>& left = scratch[0];
  std::vector<uint16_t>& right = scratch[1];
  std::vector<uint16_t>& up = scratch[2];
  std::vector<uint16_t>& down = scratch[3];
  left.resize(n), right.resize(n), up.resize(n), down.resize(n);
  parallel_rows(cv::Range(0, h), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      const size_t row = size_t(v) * w;
      nearest_before(&range[row], 1, w, reach, &left[row], 1);
      nearest_after(&range[row], 1, w, reach, &right[row], 1);
    }
  });
  // Up and down: rows in order over bands of columns, so memory is read as it lies (a
  // column-by-column walk missed the cache on every pixel: 15 % of an update).
  constexpr int kBand = 64;
  parallel_rows(cv::Range(0, (w + kBand - 1) / kBand), [&](const cv::Range& bands) {
    const int u0 = bands.start * kBand, u1 = std::min(w, bands.end * kBand);
    std::vector<int> mark(u1 - u0);
    std::fill(mark.begin(), mark.end(), -reach - 1);  // row of the last sample above
    for (int v = 0; v < h; ++v) {
      const size_t row = size_t(v) * w;
      for (int u = u0; u < u1; ++u) {
        const int d = v - mark[u - u0];
        up[row + u] = static_cast<uint16_t>(d <= reach ? d : 0);
        if (range[row + u] > 0.f) mark[u - u0] = v;
      }
    }
    std::fill(mark.begin(), mark.end(), h + reach + 1);  // row of the next sample below
    for (int v = h - 1; v >= 0; --v) {
      const size_t row = size_t(v) * w;
      for (int u = u0; u < u1; ++u) {
        const int d = mark[u - u0] - v;
        down[row + u] = static_cast<uint16_t>(d <= reach ? d : 0);
        if (range[row + u] > 0.f) mark[u - u0] = v;
      }
    }
  });
  const float rel = static_cast<float>(options.max_step_rel), abs_m = static_cast<float>(options.max_step_m);
  // The surface through samples a and b where pixel i's ray meets it: the point of the
  // segment between them that lies on the ray (exact for any surface flat between the two,
  // in every view type), or 0 when they are too far apart to be one surface.
  const auto through = [&](size_t a, size_t b, size_t i) {
    const float ra = range[a], rb = range[b];
    const float ax = ra * rays.x[a], ay = ra * rays.y[a], az = ra * rays.z[a];
    const float ex = rb * rays.x[b] - ax, ey = rb * rays.y[b] - ay, ez = rb * rays.z[b] - az;
    const float limit = rel * std::min(ra, rb) + abs_m;
    if (ex * ex + ey * ey + ez * ez > limit * limit) return 0.f;
    // Components across the ray d: P(s) = A + s E is on the ray where A_perp + s E_perp = 0.
    const float dx = rays.x[i], dy = rays.y[i], dz = rays.z[i];
    const float a_along = ax * dx + ay * dy + az * dz, e_along = ex * dx + ey * dy + ez * dz;
    const float apx = ax - a_along * dx, apy = ay - a_along * dy, apz = az - a_along * dz;
    const float epx = ex - e_along * dx, epy = ey - e_along * dy, epz = ez - e_along * dz;
    const float e2 = epx * epx + epy * epy + epz * epz;
    const float t = e2 > 0.f ? std::clamp(-(apx * epx + apy * epy + apz * epz) / e2, 0.f, 1.f) : 0.5f;
    const float r = a_along + t * e_along;
    return r > 0.f ? r : 0.f;
  };
  std::vector<float> out(range);
  size_t filled = 0, replaced = 0;
  std::mutex counts;
  parallel_rows(cv::Range(0, h), [&](const cv::Range& rows) {
    size_t my_filled = 0, my_replaced = 0;
    std::vector<int> candidates(w);
    for (int v = rows.start; v < rows.end; ++v) {
      // Most of a view has no sample within reach in any direction (beyond the lidar's
      // field, or the sky): pick the pixels that do in one branch-free sweep of the row.
      const size_t row = size_t(v) * w;
      int n = 0;
      const uint8_t* may = fillable ? fillable->data() + row : nullptr;
      for (int u = 0; u < w; ++u) {
        candidates[n] = u;
        n += (left[row + u] | right[row + u] | up[row + u] | down[row + u]) != 0 && rays.valid[row + u] &&
             (!may || may[u]);
      }
      for (int k = 0; k < n; ++k) {
        const int u = candidates[k];
        const size_t i = row + u;
        float best = 0.f;
        const int l = left[i], r = right[i], a = up[i], b = down[i];
        if (l && r && l + r <= reach) {
          const float s = through(i - l, i + r, i);
          if (s > 0.f) best = s;
        }
        if (a && b && a + b <= reach) {
          const float s = through(i - size_t(a) * w, i + size_t(b) * w, i);
          if (s > 0.f && (best == 0.f || s < best)) best = s;
        }
        // At the image's edge the partner sample may lie just outside the view: a sample
        // within reach on one side, the edge nearer than the rest of the reach on the other,
        // extends its range to the edge (the last ring before the border joins nothing else).
        if (best == 0.f) {
          const int to_left = u, to_right = w - 1 - u, to_top = v, to_bottom = h - 1 - v;
          if (l && !r && l + to_right < reach) best = range[i - l];
          if (!l && r && r + to_left < reach) best = range[i + r];
          if (a && !b && a + to_bottom < reach && (best == 0.f || range[i - size_t(a) * w] < best)) {
            best = range[i - size_t(a) * w];
          }
          if (!a && b && b + to_top < reach && (best == 0.f || range[i + size_t(b) * w] < best)) {
            best = range[i + size_t(b) * w];
          }
          if (best == 0.f || range[i] != 0.f) continue;
          out[i] = best;
          ++my_filled;
          continue;
        }
        if (range[i] == 0.f) {
          out[i] = best;
          ++my_filled;
        } else if (hidden_behind(range[i], best, rel, abs_m)) {
          out[i] = best;
          ++my_replaced;
        }
      }
    }
    std::lock_guard lock(counts);
    filled += my_filled;
    replaced += my_replaced;
  });
  stats.filled_pixels += filled;
  stats.see_through += replaced;
  return out;
}

}  // namespace

// Two passes: a lidar's points lie along its rings, a few pixels apart along a ring and
// many between rings, so in a column between two points of a ring no sample lies above or
// below. The first pass joins the points along each ring; the second joins the rings
// through those filled rows (one pass left such columns to the fixed surface: vertical
// streaks across a wall 3 m away on spot-mock, tests/spot/depth_view_test.cc).
std::vector<float> fill_gaps(const ViewRays& rays, const std::vector<float>& range, const DepthOptions& options,
                             DepthStats& stats, const std::vector<uint8_t>* fillable) {
  return fill_once(rays, fill_once(rays, range, options, stats, fillable), options, stats, fillable);
}

}  // namespace omniview
