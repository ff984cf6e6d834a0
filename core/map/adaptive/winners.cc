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

// Batches are padded to whole vectors of 8 and to at least 32 pixels: GCC's cost model
// runs the projection loops scalar below 32 (AVX2; 16 for SSE2), and the scalar loop
// costs several times the vector one. Most exact runs of a row are shorter than that.
constexpr int kVector = 8, kMinBatch = 32;

// One camera's candidates: projection (the model inlined, no call per pixel), the mask,
// and the comparison with the best so far. Compiled for baseline x86-64 and x86-64-v3.
// With occlusion, `best_unoccluded` keeps the best score before hidden points are dropped.
OMNIVIEW_MULTIVERSION
void compete(const CameraSetup& c, uint32_t cam, int n, RowScratch& s, float* best, float* out_u, float* out_v,
             uint32_t* out_cam, const CameraOccluder* occluder, const Occlusion* rule, const uint8_t* judged,
             float* best_unoccluded, uint8_t* seen_by) {
  project_camera_row(c, n, s.x.data(), s.y.data(), s.z.data(), s.valid.data(), s.u.data(), s.v.data(),
                     s.score.data());
  if (!c.camera->mask.empty()) {
    for (int i = 0; i < n; ++i) {
      if (s.score[i] != kInvalid && !mask_allows(*c.camera, s.u[i], s.v[i])) s.score[i] = kInvalid;
    }
  }
  if (best_unoccluded) {
    for (int i = 0; i < n; ++i) best_unoccluded[i] = std::min(best_unoccluded[i], s.score[i]);
  }
  if (occluder && !occluder->empty()) {
    drop_hidden(c, *occluder, *rule, n, judged, s.x.data(), s.y.data(), s.z.data(), s.u.data(), s.v.data(),
                s.score.data());
  }
  if (seen_by) {
    for (int i = 0; i < n; ++i) seen_by[i] += s.score[i] != kInvalid;
  }
  keep_better(cam, n, s.u.data(), s.v.data(), s.score.data(), best, out_u, out_v, out_cam);
}

}  // namespace

void WinnerSampler::sample(int row, const int* columns, int n, Winners& out) {
  if (n <= 0) return;
  const int padded = std::max(kMinBatch, (n + kVector - 1) / kVector * kVector);
  RowScratch& s = scratch_;
  if (s.x.size() < static_cast<size_t>(padded)) s = RowScratch(padded), best_.resize(padded);  // grows only
  if (out.u.size() < static_cast<size_t>(padded)) {
    out.u.resize(padded), out.v.resize(padded), out.cam.resize(padded), out.on_surface.resize(padded);
  }
  columns_.assign(columns, columns + n);
  columns_.resize(padded, columns[n - 1]);  // padding repeats the last column (see kMinBatch)
  view_.points_at(row, columns_.data(), padded, s.x.data(), s.y.data(), s.z.data(), s.valid.data());
  std::fill_n(best_.begin(), padded, kInvalid);
  std::fill_n(out.u.begin(), padded, 0.0f);
  std::fill_n(out.v.begin(), padded, 0.0f);
  std::fill_n(out.cam.begin(), padded, kNoCamera);
  std::copy_n(s.valid.begin(), padded, out.on_surface.begin());
  const uint8_t* judged = nullptr;
  if (keep_points_) {
    if (out.x.size() < static_cast<size_t>(padded)) {
      out.x.resize(padded), out.y.resize(padded), out.z.resize(padded);
      out.judged.resize(padded), out.better_hidden.resize(padded);
    }
    std::copy_n(s.x.begin(), padded, out.x.begin());
    std::copy_n(s.y.begin(), padded, out.y.begin());
    std::copy_n(s.z.begin(), padded, out.z.begin());
    std::fill_n(out.better_hidden.begin(), padded, 0);
  }
  if (occlusion_) {
    const size_t row_start = static_cast<size_t>(row) * static_cast<size_t>(view_.width());
    for (int i = 0; i < padded; ++i) {
      out.judged[i] = occlusion_->judged.empty() || occlusion_->judged[row_start + columns_[i]];
    }
    judged = out.judged.data();
    best_unoccluded_.resize(best_.size());
    std::fill_n(best_unoccluded_.begin(), padded, kInvalid);
  }
  if (blend_) {
    seen_by_.resize(std::max(seen_by_.size(), static_cast<size_t>(padded)));
    std::fill_n(seen_by_.begin(), padded, 0);
  }
  for (size_t ci = 0; ci < setups_.size(); ++ci) {
    compete(setups_[ci], static_cast<uint32_t>(ci), padded, s, best_.data(), out.u.data(), out.v.data(),
            out.cam.data(), occlusion_ ? &occlusion_->cameras[ci] : nullptr, occlusion_, judged,
            occlusion_ ? best_unoccluded_.data() : nullptr, blend_ ? seen_by_.data() : nullptr);
  }
  if (blend_) {
    if (out.shared.size() < static_cast<size_t>(padded)) out.shared.resize(padded);
    for (int i = 0; i < padded; ++i) {
      out.shared[i] = seen_by_[i] >= 2;
      // Seen by one camera: the blend takes it only where its feather weight is above 0
      // (outside the camera's usable region, found on a 4 px grid, it is 0).
      if (seen_by_[i] == 1) {
        const CameraSetup& c = setups_[out.cam[i]];
        if (c.feather.at<float>(static_cast<int>(out.v[i] + 0.5f), static_cast<int>(out.u[i] + 0.5f)) <= 0) {
          out.cam[i] = kNoCamera;
        }
      }
    }
  }
  if (occlusion_) {
    for (int i = 0; i < padded; ++i) out.better_hidden[i] = best_unoccluded_[i] < best_[i];
  }
}

}  // namespace omniview::map_internal
