#include <algorithm>
#include <cmath>
#include <limits>

#include "core/map/blend_kernels.h"
#include "core/map/map_kernels.h"
#include "core/map/multiversion.h"

namespace omniview::map_internal {

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
    std::fill(best.begin(), best.end(), blend ? kNoWeight : kInvalid);
    std::fill(second.begin(), second.end(), kNoWeight);
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
      keep_heaviest(c, static_cast<uint32_t>(ci), w, s.u.data(), s.v.data(), s.score.data(), best.data(),
                    second.data(), primary, secondary);
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
      const int j = i + 1 < w ? i + 1 : i - 1;  // the neighbouring pixel, for the surface's pitch
      const float p[3] = {s.x[i], s.y[i], s.z[i]};
      const float q[3] = {j >= 0 ? s.x[j] : 0.f, j >= 0 ? s.y[j] : 0.f, j >= 0 ? s.z[j] : 0.f};
      const bool neighbour = j >= 0 && s.valid[i] && s.valid[j];
      pw[i] = primary_weight(best[i], second[i],
                             band_narrowing(setups[primary[i].cam], setups[secondary[i].cam], p, q, neighbour));
    }
  }
}

}  // namespace omniview::map_internal
