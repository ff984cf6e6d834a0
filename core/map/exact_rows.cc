#include <algorithm>
#include <cmath>

#include "core/map/map_kernels.h"
#include "core/map/multiversion.h"

namespace omniview::map_internal {

// One band of output rows. Compiled twice on x86-64 (baseline SSE2 and x86-64-v3 with
// AVX2/FMA) and picked at run time, so robots with newer CPUs get 8-wide SIMD while the
// binary still runs everywhere; other architectures build it once.
OMNIVIEW_MULTIVERSION
void build_rows_exact(const View& view, const std::vector<CameraSetup>& setups, bool blend, FusionMap& map,
                      int row_begin, int row_end) {
  const int w = map.width;
  RowScratch s(w);
  std::vector<float> best(w), second(w);
  std::vector<uint32_t> offset(w), rest(w);
  for (int row = row_begin; row < row_end; ++row) {
    view.row_points(row, s.x.data(), s.y.data(), s.z.data(), s.valid.data());
    MapEntry* primary = &map.primary[static_cast<size_t>(row) * w];
    MapEntry* secondary = blend ? &map.secondary[static_cast<size_t>(row) * w] : nullptr;
    std::fill(best.begin(), best.end(), blend ? 0.0f : kInvalid);
    std::fill(second.begin(), second.end(), 0.0f);
    std::fill(rest.begin(), rest.end(), kNoRest);
    for (size_t ci = 0; ci < setups.size(); ++ci) {
      const CameraSetup& c = setups[ci];
      std::visit([&](const auto& model) {
        project_row(model, c, w, s.x.data(), s.y.data(), s.z.data(), s.valid.data(), s.u.data(), s.v.data(),
                    s.score.data());
      }, c.camera->model);
      if (!c.camera->mask.empty()) {
        for (int i = 0; i < w; ++i) {
          if (s.score[i] != kInvalid && !mask_allows(*c.camera, s.u[i], s.v[i])) s.score[i] = kInvalid;
        }
      }
      if (!blend) {
        select_nearest(c, static_cast<uint32_t>(ci), w, s.u.data(), s.v.data(), s.score.data(), best.data(),
                       offset.data(), rest.data());
        continue;
      }
      for (int i = 0; i < w; ++i) {
        if (s.score[i] == kInvalid) continue;
        const float weight = c.feather.at<float>(static_cast<int>(s.v[i] + 0.5f), static_cast<int>(s.u[i] + 0.5f));
        if (weight <= 0) continue;
        uint32_t e_rest;
        const uint32_t e_offset = encode(c.limits, s.u[i], s.v[i], static_cast<uint32_t>(ci), e_rest);
        const MapEntry e = make_entry(e_offset, e_rest);
        if (weight > best[i]) {
          second[i] = best[i];
          secondary[i] = primary[i];
          best[i] = weight;
          primary[i] = e;
        } else if (weight > second[i]) {
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
      const float total = best[i] + second[i];
      pw[i] = secondary[i].cam == kNoCamera || total <= 0
                  ? 256
                  : static_cast<uint16_t>(std::lround(256.0f * best[i] / total));
    }
  }
}

}  // namespace omniview::map_internal
