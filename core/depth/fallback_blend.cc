#include "core/depth/fallback_blend.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <opencv2/core/utility.hpp>

#include "core/map/parallel_rows.h"

namespace omniview {

BlendedSurface blend_with_fixed(const ViewRays& rays, const std::vector<float>& measured, const DepthOptions& options) {
  const int w = rays.width, h = rays.height;
  const size_t n = rays.size();
  const int band = std::clamp(static_cast<int>(std::lround(options.blend_band_deg * M_PI / 180 / rays.pixel_rad)), 1,
                              4096);
  // City-block distance (in pixels, capped at `band`) to the nearest measured pixel and its
  // depth relative to the fixed surface, carried by sweeps: along each row both ways (rows in parallel), then
  // down and up the columns (bands of columns in parallel, read row by row). The L1
  // distance separates exactly that way; O(pixels) whatever the band. The band's outline
  // is a diamond rather than a circle, which nobody sees in a fade.
  const uint16_t far = static_cast<uint16_t>(band);
  // Scratch kept per calling thread, named through references (a worker naming the
  // thread_local itself would get its own, empty, instance).
  thread_local std::vector<uint16_t> dist_scratch;
  thread_local std::vector<float> inv_scratch;
  std::vector<uint16_t>& dist = dist_scratch;
  std::vector<float>& inv = inv_scratch;  // fixed / measured range of the nearest measured pixel
  dist.resize(n);
  inv.resize(n);
  const auto take = [&](size_t i, size_t from) {
    const uint16_t d = static_cast<uint16_t>(dist[from] + 1);
    if (d < dist[i]) {
      dist[i] = d;
      inv[i] = inv[from];
    }
  };
  parallel_rows(cv::Range(0, h), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      const size_t row = size_t(v) * w;
      for (int u = 0; u < w; ++u) {
        const size_t i = row + u;
        const bool m = measured[i] > 0.f;
        dist[i] = m ? 0 : far;
        // Carried: the measured surface relative to the fixed one (fixed / measured range),
        // not its range: a neighbouring ray meets the same surface at another range (a
        // floor seen from above), and carrying the range itself raised rings of bumps.
        inv[i] = m && rays.fixed_range[i] > 0.f ? rays.fixed_range[i] / measured[i] : 1.f;
        if (u > 0) take(i, i - 1);
      }
      for (int u = w - 2; u >= 0; --u) take(row + u, row + u + 1);
    }
  });
  constexpr int kColumns = 64;
  parallel_rows(cv::Range(0, (w + kColumns - 1) / kColumns), [&](const cv::Range& bands) {
    const int u0 = bands.start * kColumns, u1 = std::min(w, bands.end * kColumns);
    for (int v = 1; v < h; ++v) {
      for (int u = u0; u < u1; ++u) take(size_t(v) * w + u, size_t(v - 1) * w + u);
    }
    for (int v = h - 2; v >= 0; --v) {
      for (int u = u0; u < u1; ++u) take(size_t(v) * w + u, size_t(v + 1) * w + u);
    }
  });
  BlendedSurface s;
  s.range.resize(n);
  s.measured.resize(n);
  const float inv_band = 1.f / static_cast<float>(band);
  // Only measured depth at or behind the fixed surface fades into it (a wall going on above
  // a lidar's top ring). Measured depth well in front of it is an object, and past the
  // object's measured edge the world goes on behind it: there the edge is a real step, and a
  // fade would lift the floor beside a pillar towards the pillar's range.
  constexpr float kNearer = 1.1f;  // fixed / measured > 1.1: the measured surface is in front
  for (size_t i = 0; i < n; ++i) {
    const float fixed = rays.fixed_range[i];
    if (dist[i] == 0) {
      s.range[i] = measured[i];
      s.measured[i] = 255;
      ++s.measured_pixels;
    } else if (dist[i] < far && fixed > 0.f && inv[i] < kNearer) {
      const float share = 1.f - static_cast<float>(dist[i]) * inv_band;
      s.range[i] = fixed / (share * inv[i] + (1.f - share));
      s.measured[i] = static_cast<uint8_t>(std::lround(255.f * share));
      ++s.blended_pixels;
    } else {
      s.range[i] = fixed;  // 0 where the fixed surface has no point either
      s.measured[i] = 0;
    }
  }
  return s;
}

}  // namespace omniview
