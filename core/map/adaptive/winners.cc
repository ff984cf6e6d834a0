#include "core/map/adaptive/winners.h"

#include <algorithm>
#include <bit>

#include "core/map/multiversion.h"

namespace omniview::map_internal {
namespace {

// Where camera `cam`'s candidates beat the best so far, they win. Strict, so ties go to
// the lower camera index, as in the per-pixel builder. Selects only: vectorises.
[[gnu::always_inline]] inline void keep_better(uint32_t cam, int n, const float* __restrict u, const float* __restrict v,
                 const float* __restrict score, float* __restrict best, float* __restrict out_u,
                 float* __restrict out_v, uint32_t* __restrict out_cam) {
  for (int i = 0; i < n; ++i) {
    // Bit masks rather than ?: on floats, which GCC leaves as branches here.
    const uint32_t take = 0u - static_cast<uint32_t>(score[i] < best[i]);
    best[i] = score[i] < best[i] ? score[i] : best[i];
    out_u[i] = std::bit_cast<float>((std::bit_cast<uint32_t>(u[i]) & take) | (std::bit_cast<uint32_t>(out_u[i]) & ~take));
    out_v[i] = std::bit_cast<float>((std::bit_cast<uint32_t>(v[i]) & take) | (std::bit_cast<uint32_t>(out_v[i]) & ~take));
    out_cam[i] = (cam & take) | (out_cam[i] & ~take);
  }
}

// One camera's candidates: projection (the model inlined, no call per pixel), the mask,
// and the comparison with the best so far. Compiled for baseline x86-64 and x86-64-v3.
OMNIVIEW_MULTIVERSION
void compete(const CameraSetup& c, uint32_t cam, int n, RowScratch& s, float* best, float* out_u, float* out_v,
             uint32_t* out_cam) {
  visit_model(c.camera->model, [&](const auto& model) [[gnu::always_inline]] {
    project_row(model, c, n, s.x.data(), s.y.data(), s.z.data(), s.valid.data(), s.u.data(), s.v.data(),
                s.score.data());
  });
  if (!c.camera->mask.empty()) {
    for (int i = 0; i < n; ++i) {
      if (s.score[i] != kInvalid && !mask_allows(*c.camera, s.u[i], s.v[i])) s.score[i] = kInvalid;
    }
  }
  keep_better(cam, n, s.u.data(), s.v.data(), s.score.data(), best, out_u, out_v, out_cam);
}

}  // namespace

void WinnerSampler::sample(int row, const int* columns, int n, Winners& out, size_t at) {
  if (n <= 0) return;
  RowScratch& s = scratch_;
  if (s.x.size() < static_cast<size_t>(n)) s = RowScratch(n), best_.resize(n);  // grows, never shrinks
  view_.points_at(row, columns, n, s.x.data(), s.y.data(), s.z.data(), s.valid.data());
  std::fill_n(best_.begin(), n, kInvalid);
  std::fill_n(out.u.begin() + at, n, 0.0f);
  std::fill_n(out.v.begin() + at, n, 0.0f);
  std::fill_n(out.cam.begin() + at, n, kNoCamera);
  std::copy_n(s.valid.begin(), n, out.on_surface.begin() + at);
  for (size_t ci = 0; ci < setups_.size(); ++ci) {
    compete(setups_[ci], static_cast<uint32_t>(ci), n, s, best_.data(), out.u.data() + at, out.v.data() + at,
            out.cam.data() + at);
  }
}

}  // namespace omniview::map_internal
