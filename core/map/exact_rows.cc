#include <algorithm>
#include <cmath>
#include <limits>

#include "core/map/map_kernels.h"
#include "core/map/multiversion.h"

namespace omniview::map_internal {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// How much narrower the blend band between cameras a and b gets at pixel i of the row in
// `s`: the two copies of an object at infinity (or at half the surface's distance) lie
// about the baseline's part across the line of sight apart on the surface, which divided by
// the surface's spacing between neighbouring view pixels is their distance in the view.
float band_narrowing(const CameraSetup& a, const CameraSetup& b, const RowScratch& s, int i, int w) {
  const int j = i + 1 < w ? i + 1 : i - 1;
  if (j < 0 || !s.valid[i] || !s.valid[j]) return 1;
  const float p[3] = {s.x[i], s.y[i], s.z[i]};
  const float pitch = std::hypot(s.x[j] - p[0], s.y[j] - p[1], s.z[j] - p[2]);
  float d[3], base[3];
  for (int k = 0; k < 3; ++k) {
    d[k] = p[k] - 0.5f * (a.centre_view[k] + b.centre_view[k]);
    base[k] = a.centre_view[k] - b.centre_view[k];
  }
  const float norm = std::hypot(d[0], d[1], d[2]);
  if (!(pitch > 0) || !(norm > 0)) return 1;
  const float along = (base[0] * d[0] + base[1] * d[1] + base[2] * d[2]) / norm;
  const float base2 = base[0] * base[0] + base[1] * base[1] + base[2] * base[2];
  const float across = std::sqrt(std::max(0.0f, base2 - along * along));
  const float ghost_px = across / pitch;
  return std::clamp(ghost_px / kGhostTolerancePx, 1.0f, kMaxBandNarrowing);
}

}  // namespace

// One band of output rows. Compiled twice on x86-64 (baseline SSE2 and x86-64-v3 with
// AVX2/FMA) and picked at run time, so robots with newer CPUs get 8-wide SIMD while the
// binary still runs everywhere; other architectures build it once.
OMNIVIEW_MULTIVERSION
void build_rows_exact(const View& view, const std::vector<CameraSetup>& setups, bool blend, FusionMap& map,
                      int row_begin, int row_end, const Occlusion* occlusion) {
  const int w = map.width;
  RowScratch s(w);
  std::vector<float> best(w), second(w);
  std::vector<uint32_t> offset(w), rest(w);
  for (int row = row_begin; row < row_end; ++row) {
    view.row_points(row, s.x.data(), s.y.data(), s.z.data(), s.valid.data());
    MapEntry* primary = &map.primary[static_cast<size_t>(row) * w];
    MapEntry* secondary = blend ? &map.secondary[static_cast<size_t>(row) * w] : nullptr;
    // Blend: log weights, -infinity for none.
    std::fill(best.begin(), best.end(), blend ? -kInfinity : kInvalid);
    std::fill(second.begin(), second.end(), -kInfinity);
    std::fill(rest.begin(), rest.end(), kNoRest);
    for (size_t ci = 0; ci < setups.size(); ++ci) {
      const CameraSetup& c = setups[ci];
      project_camera_row(c, w, s.x.data(), s.y.data(), s.z.data(), s.valid.data(), s.u.data(), s.v.data(),
                         s.score.data());
      if (!c.camera->mask.empty()) {
        for (int i = 0; i < w; ++i) {
          if (s.score[i] != kInvalid && !mask_allows(*c.camera, s.u[i], s.v[i])) s.score[i] = kInvalid;
        }
      }
      // Here, where the camera is chosen: one rule for nearest-centre and blend alike.
      if (occlusion && !occlusion->cameras[ci].empty()) {
        const uint8_t* judged = occlusion->judged.empty() ? nullptr : &occlusion->judged[size_t(row) * w];
        drop_hidden(c, occlusion->cameras[ci], *occlusion, w, judged, s.x.data(), s.y.data(), s.z.data(), s.u.data(),
                    s.v.data(), s.score.data());
      }
      if (!blend) {
        select_nearest(c, static_cast<uint32_t>(ci), w, s.u.data(), s.v.data(), s.score.data(), best.data(),
                       offset.data(), rest.data());
        continue;
      }
      for (int i = 0; i < w; ++i) {
        if (s.score[i] == kInvalid) continue;
        const float feather = c.feather.at<float>(static_cast<int>(s.v[i] + 0.5f), static_cast<int>(s.u[i] + 0.5f));
        if (feather <= 0) continue;
        // In the log domain: the centre term's factors span many orders of magnitude. Most
        // of a camera's pixels are at full feather weight, and their log is 0.
        const float weight = (feather < 1 ? std::log(feather) : 0.0f) - c.centre_falloff * std::sqrt(s.score[i]);
        if (weight <= second[i]) continue;  // encoded only when kept
        uint32_t e_rest;
        const uint32_t e_offset = encode(c.limits, s.u[i], s.v[i], static_cast<uint32_t>(ci), e_rest);
        const MapEntry e = make_entry(e_offset, e_rest);
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
    if (!blend) {
      for (int i = 0; i < w; ++i) primary[i] = make_entry(offset[i], rest[i]);
      continue;
    }
    uint16_t* pw = &map.primary_weight[static_cast<size_t>(row) * w];
    for (int i = 0; i < w; ++i) {
      if (secondary[i].cam == kNoCamera) {
        pw[i] = 256;
        continue;
      }
      // The primary's share, 1 / (1 + w2 / w1), in [0.5, 1], then narrowed by parallax.
      float share = 1.0f / (1.0f + std::exp(second[i] - best[i]));
      share = std::min(1.0f, 0.5f + (share - 0.5f) * band_narrowing(setups[primary[i].cam], setups[secondary[i].cam],
                                                                     s, i, w));
      pw[i] = static_cast<uint16_t>(std::lround(256.0f * share));
    }
  }
}

}  // namespace omniview::map_internal
