#include "core/map/footprint.h"

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

namespace omniview {
namespace {

constexpr int kStep = 4;  // footprints measured every kStep output pixels

// Entry position in its camera's full-size image.
inline void position(const FusionMap& map, const MapEntry& e, float& u, float& v) {
  const uint32_t w = static_cast<uint32_t>(map.camera_sizes[e.cam].width);
  u = static_cast<float>(e.offset % w) + e.fx / 256.0f;
  v = static_cast<float>(e.offset / w) + e.fy / 256.0f;
}

// Re-addresses a level-0 entry in the level-`level` image (pyrDown: level pixel i is
// centred on pixel 2i of the level above).
MapEntry at_level(const FusionMap& map, const MapEntry& e, int level) {
  float u, v;
  position(map, e, u, v);
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
  const int bw = (map.width + kStep - 1) / kStep, bh = (map.height + kStep - 1) / kStep;
  std::vector<uint8_t> block_level(static_cast<size_t>(bw) * bh, 0);
  const auto entry = [&](int x, int y) -> const MapEntry& { return map.primary[static_cast<size_t>(y) * map.width + x]; };
  // Pass 1, read only: the footprint per block, from its corner and the grid points to its
  // right and below (same camera at all three, else the block stays at level 0: a seam).
  cv::parallel_for_(cv::Range(0, bh), [&](const cv::Range& rows) {
    for (int by = rows.start; by < rows.end; ++by) {
      const int ya = std::min(by * kStep, map.height - 2), yb = std::min(ya + kStep, map.height - 1);
      for (int bx = 0; bx < bw; ++bx) {
        const int xa = std::min(bx * kStep, map.width - 2), xb = std::min(xa + kStep, map.width - 1);
        const MapEntry &e0 = entry(xa, ya), &ex = entry(xb, ya), &ey = entry(xa, yb);
        if (e0.cam == kNoCamera || ex.cam != e0.cam || ey.cam != e0.cam) continue;
        float u0, v0, ux, vx, uy, vy;
        position(map, e0, u0, v0);
        position(map, ex, ux, vx);
        position(map, ey, uy, vy);
        const float along_x = std::hypot(ux - u0, vx - v0) / static_cast<float>(xb - xa);
        const float along_y = std::hypot(uy - u0, vy - v0) / static_cast<float>(yb - ya);
        // The footprint's shorter axis decides (longer-axis aliasing beats blurring both
        // axes), one level finer than mip-mapping's floor rule: pyrDown's Gaussian plus the
        // bilinear tap at level L already average over ~2^(L+1) pixels. Chosen on the golden
        // panoramas (tests/golden/footprint_test.cc), where it measured best.
        const float shorter = std::min(along_x, along_y);
        const int level = (shorter >= 4.0f) + (shorter >= 8.0f) + (shorter >= 16.0f);
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
  cv::parallel_for_(cv::Range(0, bh), [&](const cv::Range& rows) {
    for (int by = rows.start; by < rows.end; ++by) {
      for (int bx = 0; bx < bw; ++bx) {
        const size_t b = static_cast<size_t>(by) * bw + bx;
        if (block_level[b] == 0) continue;
        for (int y = by * kStep; y < std::min((by + 1) * kStep, map.height); ++y) {
          for (int x = bx * kStep; x < std::min((bx + 1) * kStep, map.width); ++x) {
            MapEntry& e = map.primary[static_cast<size_t>(y) * map.width + x];
            if (e.cam == block_cam[b]) e = at_level(map, e, block_level[b]);
          }
        }
      }
    }
  });
}

}  // namespace omniview
