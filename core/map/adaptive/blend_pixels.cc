#include "core/map/adaptive/blend_pixels.h"

#include <algorithm>

#include "core/map/blend_kernels.h"
#include "core/map/multiversion.h"

namespace omniview::map_internal {
namespace {

// One camera's candidates at the pixels in `s`: projection (the model inlined), its mask,
// the occlusion test, and the blend rule. Compiled for baseline x86-64 and x86-64-v3.
OMNIVIEW_MULTIVERSION
void weigh_in(const CameraSetup& c, uint32_t cam, int n, RowScratch& s, const CameraOccluder* occluder,
              const Occlusion* rule, const uint8_t* judged, float* best, float* second, MapEntry* primary,
              MapEntry* secondary) {
  project_camera_row(c, n, s.x.data(), s.y.data(), s.z.data(), s.valid.data(), s.u.data(), s.v.data(),
                     s.score.data());
  if (!c.camera->mask.empty()) {
    for (int i = 0; i < n; ++i) {
      if (s.score[i] != kInvalid && !mask_allows(*c.camera, s.u[i], s.v[i])) s.score[i] = kInvalid;
    }
  }
  if (occluder && !occluder->empty()) {
    drop_hidden(c, *occluder, *rule, n, judged, s.x.data(), s.y.data(), s.z.data(), s.u.data(), s.v.data(),
                s.score.data());
  }
  keep_heaviest(c, cam, n, s.u.data(), s.v.data(), s.score.data(), best, second, primary, secondary);
}

}  // namespace

void BlendPixels::write(int row, const int* columns, int n, FusionMap& map, std::vector<uint8_t>& used) {
  if (n <= 0) return;
  const int w = view_.width();
  RowScratch& s = scratch_;
  if (s.x.size() < static_cast<size_t>(n)) {  // grows only
    s = RowScratch(n);
    qx_.resize(n), qy_.resize(n), qz_.resize(n), q_valid_.resize(n), best_.resize(n), second_.resize(n);
    judged_.resize(n), neighbours_.resize(n), blend_index_.resize(n), primary_.resize(n), secondary_.resize(n);
  }
  view_.points_at(row, columns, n, s.x.data(), s.y.data(), s.z.data(), s.valid.data());
  std::fill_n(best_.begin(), n, kNoWeight);
  std::fill_n(second_.begin(), n, kNoWeight);
  std::fill_n(primary_.begin(), n, kBlackEntry);
  std::fill_n(secondary_.begin(), n, kBlackEntry);
  const uint8_t* judged = nullptr;
  if (occlusion_ && !occlusion_->judged.empty()) {
    const uint8_t* judged_row = &occlusion_->judged[static_cast<size_t>(row) * w];
    for (int i = 0; i < n; ++i) judged_[i] = judged_row[columns[i]];
    judged = judged_.data();
  }
  for (size_t ci = 0; ci < setups_.size(); ++ci) {
    weigh_in(setups_[ci], static_cast<uint32_t>(ci), n, s, occlusion_ ? &occlusion_->cameras[ci] : nullptr,
             occlusion_, judged, best_.data(), second_.data(), primary_.data(), secondary_.data());
  }
  const size_t start = static_cast<size_t>(row) * static_cast<size_t>(w);
  int blended = 0;  // pixels with a second camera, gathered at the front of neighbours_
  for (int i = 0; i < n; ++i) {
    const size_t at = start + columns[i];
    map.primary[at] = primary_[i];
    map.secondary[at] = secondary_[i];
    map.primary_weight[at] = 256;
    if (primary_[i].cam != kNoCamera) used[primary_[i].cam] = 1;
    if (secondary_[i].cam == kNoCamera) continue;
    used[secondary_[i].cam] = 1;
    blend_index_[blended] = i;
    // The right-hand neighbour (left at the last column): the surface's pitch there narrows
    // the seam's band, as in the per-pixel builder.
    neighbours_[blended++] = columns[i] + 1 < w ? columns[i] + 1 : std::max(0, columns[i] - 1);
  }
  if (blended == 0) return;
  view_.points_at(row, neighbours_.data(), blended, qx_.data(), qy_.data(), qz_.data(), q_valid_.data());
  for (int k = 0; k < blended; ++k) {
    const int i = blend_index_[k];
    const float p[3] = {s.x[i], s.y[i], s.z[i]};
    const float q[3] = {qx_[k], qy_[k], qz_[k]};
    const bool neighbour = w > 1 && s.valid[i] && q_valid_[k];
    map.primary_weight[start + columns[i]] = primary_weight(
        best_[i], second_[i], band_narrowing(setups_[primary_[i].cam], setups_[secondary_[i].cam], p, q, neighbour));
  }
}

}  // namespace omniview::map_internal
