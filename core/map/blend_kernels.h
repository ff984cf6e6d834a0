// The blend policy's rule at one pixel, shared by the per-pixel builder (exact_rows.cc)
// and the adaptive builder's exact pixels (adaptive/blend_pixels.h), so both make the same
// entries: each camera that sees the pixel weighs in with its feather weight at the pixel
// times a falloff from its image centre; the heaviest two are kept, and the primary's share
// narrows where the two would show an object off the surface doubled.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/map/map_kernels.h"

namespace omniview::map_internal {

// Log weights: the centre term's factors span many orders of magnitude.
inline constexpr float kNoWeight = -std::numeric_limits<float>::infinity();

// Camera `cam`'s candidates (u, v, score; kInvalid where it does not see) against the
// heaviest two so far (`best`, `second` log weights, kNoWeight for none). A candidate is
// encoded only when it is kept.
inline void keep_heaviest(const CameraSetup& c, uint32_t cam, int n, const float* u, const float* v,
                          const float* score, float* best, float* second, MapEntry* primary, MapEntry* secondary) {
  for (int i = 0; i < n; ++i) {
    if (score[i] == kInvalid) continue;
    const float feather = c.feather.at<float>(static_cast<int>(v[i] + 0.5f), static_cast<int>(u[i] + 0.5f));
    if (feather <= 0) continue;
    // Most of a camera's pixels are at full feather weight, and their log is 0.
    const float weight = (feather < 1 ? std::log(feather) : 0.0f) - c.centre_falloff * std::sqrt(score[i]);
    if (weight <= second[i]) continue;
    uint32_t rest;
    const uint32_t offset = encode(c.limits, u[i], v[i], cam, rest);
    const MapEntry e = make_entry(offset, rest);
    if (weight > best[i]) {
      second[i] = best[i];
      secondary[i] = primary[i];
      best[i] = weight;
      primary[i] = e;
    } else {
      second[i] = weight;
      secondary[i] = e;
    }
  }
}

// How much narrower the blend band between cameras a and b gets at surface point p, whose
// neighbouring view pixel's surface point is q (`neighbour`: q exists): the two copies of an
// object at infinity (or at half the surface's distance) lie about the baseline's part
// across the line of sight apart on the surface, which divided by the surface's spacing
// between neighbouring view pixels is their distance in the view.
inline float band_narrowing(const CameraSetup& a, const CameraSetup& b, const float (&p)[3], const float (&q)[3],
                            bool neighbour) {
  if (!neighbour) return 1;
  // Plain square roots: std::hypot's scaling is not needed at these magnitudes and cost a
  // tenth of a blend map's build.
  const float pitch = std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]));
  float d[3], base[3];
  for (int k = 0; k < 3; ++k) {
    d[k] = p[k] - 0.5f * (a.centre_view[k] + b.centre_view[k]);
    base[k] = a.centre_view[k] - b.centre_view[k];
  }
  const float norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(pitch > 0) || !(norm > 0)) return 1;
  const float along = (base[0] * d[0] + base[1] * d[1] + base[2] * d[2]) / norm;
  const float base2 = base[0] * base[0] + base[1] * base[1] + base[2] * base[2];
  const float across = std::sqrt(std::max(0.0f, base2 - along * along));
  const float ghost_px = across / pitch;
  return std::clamp(ghost_px / kGhostTolerancePx, 1.0f, kMaxBandNarrowing);
}

// The primary's weight out of 256 (256: the primary alone), from the two log weights.
inline uint16_t primary_weight(float best, float second, float narrowing) {
  // The primary's share, 1 / (1 + w2 / w1), in [0.5, 1], then narrowed by parallax.
  float share = 1.0f / (1.0f + std::exp(second - best));
  share = std::min(1.0f, 0.5f + (share - 0.5f) * narrowing);
  return static_cast<uint16_t>(std::lround(256.0f * share));
}

}  // namespace omniview::map_internal
