#include "core/map/footprint.h"

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

#include "core/map/parallel_rows.h"

namespace omniview {
namespace {

constexpr int kStep = 4;  // footprints measured every kStep output pixels

// Entry position in its camera's full-size image. The row comes from a multiplication by
// the reciprocal width (an integer division per entry cost more than the rest of pass 1),
// corrected by one where rounding lands next to it.
inline void position(const FusionMap& map, const std::vector<double>& inv_width, const MapEntry& e, float& u,
                     float& v) {
  const uint32_t w = static_cast<uint32_t>(map.camera_sizes[e.cam].width);
  uint32_t y = static_cast<uint32_t>(e.offset * inv_width[e.cam]);
  if (y * w > e.offset) --y;
  if ((y + 1) * w <= e.offset) ++y;
  u = static_cast<float>(e.offset - y * w) + e.fx / 256.0f;
  v = static_cast<float>(y) + e.fy / 256.0f;
}

// Re-addresses a level-0 entry in the level-`level` image (pyrDown: level pixel i is
// centred on pixel 2i of the level above).
MapEntry at_level(const FusionMap& map, const std::vector<double>& inv_width, const MapEntry& e, int level) {
  float u, v;
  position(map, inv_width, e, u, v);
  const cv::Size s = pyramid_level_size(map.camera_sizes[e.cam], level);
  const float scale = 1.0f / static_cast<float>(1 << level);
  const float ul = std::clamp(u * scale, 0.0f, static_cast<float>(s.width - 1));
  const float vl = std::clamp(v * scale, 0.0f, static_cast<float>(s.height - 1));
  const int x0 = std::min(static_cast<int>(ul), s.width - 2), y0 = std::min(static_cast<int>(vl), s.height - 2);
  MapEntry out = e;
  out.offset = static_cast<uint32_t>(y0 * s.width + x0);
  out.fx = static_cast<uint8_t>(std::min(255.0f, (ul - static_cast<float>(x0)) * 256.0f + 0.5f));
  out.fy = static_cast<uint8_t>(std::min(255.0f, (vl - static_cast<float>(y0)) * 256.0f + 0.5f));
  out.level = static_cast<uint8_t>(level);
  return out;
}

}  // namespace

cv::Size pyramid_level_size(cv::Size s, int level) {
  for (int i = 0; i < level; ++i) s = cv::Size((s.width + 1) / 2, (s.height + 1) / 2);
  return s;
}

void assign_footprint_levels(FusionMap& map) {
  const size_t cameras = map.camera_sizes.size();
  map.camera_levels.assign(cameras, 0);
  if (map.width < 2 || map.height < 2 || !map.secondary.empty() || map.primary.empty()) return;
  std::vector<int> deepest(cameras, 0);  // keep every level at least 2x2
  for (size_t c = 0; c < cameras; ++c) {
    while (deepest[c] < kMaxPyramidLevel) {
      const cv::Size next = pyramid_level_size(map.camera_sizes[c], deepest[c] + 1);
      if (next.width < 2 || next.height < 2) break;
      ++deepest[c];
    }
  }
  std::vector<double> inv_width(cameras);
  for (size_t c = 0; c < cameras; ++c) inv_width[c] = 1.0 / map.camera_sizes[c].width;
  const auto entry0 = [&](int x, int y) -> const MapEntry& { return map.primary[static_cast<size_t>(y) * map.width + x]; };
  // Early out for views that do not shrink (most): footprints on a 16-pixel grid, with a
  // margin below the 4-pixel threshold, before measuring every 4x4 block.
  bool any_shrink = false;
  for (int ya = 0; ya < map.height - 1 && !any_shrink; ya += 4 * kStep) {
    const int yb = std::min(ya + 4 * kStep, map.height - 1);
    for (int xa = 0; xa < map.width - 1 && !any_shrink; xa += 4 * kStep) {
      const int xb = std::min(xa + 4 * kStep, map.width - 1);
      const MapEntry &e0 = entry0(xa, ya), &ex = entry0(xb, ya), &ey = entry0(xa, yb);
      if (e0.cam == kNoCamera || ex.cam != e0.cam || ey.cam != e0.cam) continue;
      float u0, v0, ux, vx, uy, vy;
      position(map, inv_width, e0, u0, v0);
      position(map, inv_width, ex, ux, vx);
      position(map, inv_width, ey, uy, vy);
      const float dx = static_cast<float>(xb - xa), dy = static_cast<float>(yb - ya);
      const float along_x2 = ((ux - u0) * (ux - u0) + (vx - v0) * (vx - v0)) / (dx * dx);
      const float along_y2 = ((uy - u0) * (uy - u0) + (vy - v0) * (vy - v0)) / (dy * dy);
      any_shrink = std::min(along_x2, along_y2) >= 9.0f;  // 3 camera pixels per view pixel
    }
  }
  if (!any_shrink) return;
  const int bw = (map.width + kStep - 1) / kStep, bh = (map.height + kStep - 1) / kStep;
  std::vector<uint8_t> block_level(static_cast<size_t>(bw) * bh, 0);
  const auto entry = [&](int x, int y) -> const MapEntry& { return map.primary[static_cast<size_t>(y) * map.width + x]; };
  // Pass 1, read only: the footprint per block, from its corner and the grid points to its
  // right and below (same camera at all three, else the block stays at level 0: a seam).
  parallel_rows(cv::Range(0, bh), [&](const cv::Range& rows) {
    for (int by = rows.start; by < rows.end; ++by) {
      const int ya = std::min(by * kStep, map.height - 2), yb = std::min(ya + kStep, map.height - 1);
      for (int bx = 0; bx < bw; ++bx) {
        const int xa = std::min(bx * kStep, map.width - 2), xb = std::min(xa + kStep, map.width - 1);
        const MapEntry &e0 = entry(xa, ya), &ex = entry(xb, ya), &ey = entry(xa, yb);
        if (e0.cam == kNoCamera || ex.cam != e0.cam || ey.cam != e0.cam) continue;
        float u0, v0, ux, vx, uy, vy;
        position(map, inv_width, e0, u0, v0);
        position(map, inv_width, ex, ux, vx);
        position(map, inv_width, ey, uy, vy);
        const float dx = static_cast<float>(xb - xa), dy = static_cast<float>(yb - ya);
        const float along_x2 = ((ux - u0) * (ux - u0) + (vx - v0) * (vx - v0)) / (dx * dx);
        const float along_y2 = ((uy - u0) * (uy - u0) + (vy - v0) * (vy - v0)) / (dy * dy);
        // The footprint's shorter axis decides (longer-axis aliasing beats blurring both
        // axes), one level finer than mip-mapping's floor rule: pyrDown's Gaussian plus the
        // bilinear tap at level L already average over ~2^(L+1) pixels. Chosen on the golden
        // panoramas (tests/golden/footprint_test.cc), where it measured best.
        const float shorter2 = std::min(along_x2, along_y2);  // squared, in camera pixels per view pixel
        const int level = (shorter2 >= 16.0f) + (shorter2 >= 64.0f) + (shorter2 >= 256.0f);
        block_level[static_cast<size_t>(by) * bw + bx] = static_cast<uint8_t>(std::min(level, deepest[e0.cam]));
      }
    }
  });
  // Pass 2: re-address the entries of shrinking blocks that read the block's camera.
  std::vector<uint8_t> block_cam(block_level.size(), kNoCamera);
  for (int by = 0; by < bh; ++by) {
    for (int bx = 0; bx < bw; ++bx) {
      const uint8_t level = block_level[static_cast<size_t>(by) * bw + bx];
      if (level == 0) continue;
      const uint8_t cam = entry(std::min(bx * kStep, map.width - 2), std::min(by * kStep, map.height - 2)).cam;
      block_cam[static_cast<size_t>(by) * bw + bx] = cam;
      map.camera_levels[cam] = std::max(map.camera_levels[cam], level);
    }
  }
  parallel_rows(cv::Range(0, bh), [&](const cv::Range& rows) {
    for (int by = rows.start; by < rows.end; ++by) {
      for (int bx = 0; bx < bw; ++bx) {
        const size_t b = static_cast<size_t>(by) * bw + bx;
        if (block_level[b] == 0) continue;
        for (int y = by * kStep; y < std::min((by + 1) * kStep, map.height); ++y) {
          for (int x = bx * kStep; x < std::min((bx + 1) * kStep, map.width); ++x) {
            MapEntry& e = map.primary[static_cast<size_t>(y) * map.width + x];
            if (e.cam == block_cam[b]) e = at_level(map, inv_width, e, block_level[b]);
          }
        }
      }
    }
  });
}

}  // namespace omniview
