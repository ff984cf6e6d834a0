// Phase 2 of CloudColourer::colour for nearest-centre fusion: each point takes the camera
// whose pixel is nearest its image centre among those that see it unhidden.
#include <limits>

#include "core/cloud/colourer_internal.h"
#include "core/rig/camera_index.h"

namespace omniview {

namespace {

// Per-thread scratch for one chunk of points: the best camera so far and its pixel.
struct Best {
  std::vector<float> score, u, v;
  std::vector<uint8_t> cam, hidden;
  void reset(size_t len) {
    score.assign(len, std::numeric_limits<float>::max());
    u.resize(len);
    v.resize(len);
    cam.assign(len, kNoCamera);
    hidden.assign(len, 0);
  }
};

// One camera over a chunk of `len` points, without branches (runs of points a camera sees
// or not are long, but which camera wins changes from point to point): a point the camera
// does not image reads some cell of the occluder and is then ignored.
template <bool kOcclusion>
void fuse_camera(float inv_cell, float offset, float max_cx, float max_cy, int cols, float cx, float cy,
                 float inv_half_diag2, float rel, float abs_tol, uint8_t c, const uint8_t* __restrict valid,
                 const float* __restrict u, const float* __restrict v, const float* __restrict range,
                 const float* __restrict occluder, size_t len, float* __restrict best_score, float* __restrict best_u,
                 float* __restrict best_v, uint8_t* __restrict best_cam, uint8_t* __restrict hidden) {
  for (size_t j = 0; j < len; ++j) {
    const int sees = valid[j] & 1;
    int hid = 0;
    if constexpr (kOcclusion) {
      // Inside the image (bit 0) the cell is inside the buffer; elsewhere u, v may be NaN
      // or huge, so they are clamped before they become an index.
      const float cu0 = u[j] * inv_cell + offset, cv0 = v[j] * inv_cell + offset;
      const float cu = (cu0 >= 0.f && cu0 < max_cx) ? cu0 : 0.f;
      const float cv = (cv0 >= 0.f && cv0 < max_cy) ? cv0 : 0.f;
      const float nearest = occluder[static_cast<int>(cv) * cols + static_cast<int>(cu)];
      hid = sees & (range[j] > nearest * rel + abs_tol);
    }
    const float du = u[j] - cx, dv = v[j] - cy;
    const float score = (du * du + dv * dv) * inv_half_diag2;
    // Cameras in rig order, a strictly better score wins: as the point-by-point loop did.
    const int better = sees & (hid ^ 1) & (score < best_score[j]);
    best_score[j] = better ? score : best_score[j];
    best_u[j] = better ? u[j] : best_u[j];
    best_v[j] = better ? v[j] : best_v[j];
    best_cam[j] = better ? c : best_cam[j];
    hidden[j] |= static_cast<uint8_t>(hid);
  }
}

}  // namespace

// Camera by camera over points [begin, end): each pass reads one camera's arrays in order
// (a few streams instead of five cameras' at once), then one pass samples the winners.
void CloudColourer::nearest_centre(PointCloud& cloud, const CameraImages& input, const ColourOptions& options,
                                   size_t begin, size_t end) const {
  const size_t len = end - begin;
  thread_local Best best;
  best.reset(len);
  const float rel = 1.f + options.occlusion_tolerance_rel, abs_tol = options.occlusion_tolerance_m;
  for (size_t c = 0; c < passes_.size(); ++c) {
    const CameraPass& pass = passes_[c];
    if (!pass.active) continue;
    const CameraSetup& s = *cameras_[c];
    (options.occlusion ? fuse_camera<true> : fuse_camera<false>)(
        pass.inv_cell, pass.offset, static_cast<float>(pass.cols), static_cast<float>(pass.rows), pass.cols, s.cx,
        s.cy, s.inv_half_diag2, rel, abs_tol, static_cast<uint8_t>(c), pass.valid.data() + begin,
        pass.u.data() + begin, pass.v.data() + begin, pass.range.data() + begin, pass.occluder.data(), len,
        best.score.data(), best.u.data(), best.v.data(), best.cam.data(), best.hidden.data());
  }
  for (size_t j = 0; j < len; ++j) {
    uint8_t& flags = cloud.flags[begin + j];
    if (flags & cloud_flags::kSelf) continue;
    if (best.cam[j] == kNoCamera) {
      if (best.hidden[j]) flags |= cloud_flags::kOccluded;
      continue;
    }
    float rgb[3];
    cloud_internal::sample(input.images[best.cam[j]], best.u[j], best.v[j], rgb);
    cloud.rgb[begin + j] = {cloud_internal::to_byte(rgb[0]), cloud_internal::to_byte(rgb[1]),
                            cloud_internal::to_byte(rgb[2])};
    cloud.camera[begin + j] = best.cam[j];
    flags |= cloud_flags::kColoured;
  }
}

}  // namespace omniview
