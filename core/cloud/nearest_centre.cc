// Phase 2 of CloudColourer::colour for nearest-centre fusion: each point takes the camera
// whose pixel is nearest its image centre among those that see it unhidden.
#include <limits>

#include "core/cloud/colourer_internal.h"
#include "core/rig/camera_index.h"

namespace omniview {

// Nearest-centre fusion of points [begin, end), camera by camera: each pass reads one
// camera's arrays in order (a few streams instead of five cameras' at once), and the
// per-point choice stays as in the point-by-point loop (cameras in rig order, strictly
// better scores win), so the result is the same.
void CloudColourer::nearest_centre(PointCloud& cloud, const CameraImages& input, const ColourOptions& options,
                                   size_t begin, size_t end) const {
  const size_t len = end - begin;
  std::vector<float> best(len, std::numeric_limits<float>::max()), best_u(len), best_v(len);
  std::vector<uint8_t> best_cam(len, kNoCamera), hidden(len, 0);
  const float rel = 1.f + options.occlusion_tolerance_rel, abs_tol = options.occlusion_tolerance_m;
  for (size_t c = 0; c < passes_.size(); ++c) {
    const CameraPass& pass = passes_[c];
    if (!pass.active) continue;
    const CameraSetup& s = *cameras_[c];
    const uint8_t* valid = pass.valid.data() + begin;
    const float* u = pass.u.data() + begin;
    const float* v = pass.v.data() + begin;
    const float* range = pass.range.data() + begin;
    for (size_t j = 0; j < len; ++j) {
      if (!(valid[j] & 1)) continue;
      if (options.occlusion) {
        const float nearest = pass.occluder.ptr<float>(static_cast<int>(v[j] * pass.inv_cell + pass.offset))
                                  [static_cast<int>(u[j] * pass.inv_cell + pass.offset)];
        if (range[j] > nearest * rel + abs_tol) {
          hidden[j] = 1;
          continue;
        }
      }
      const float du = u[j] - s.cx, dv = v[j] - s.cy;
      const float score = (du * du + dv * dv) * s.inv_half_diag2;
      if (score < best[j]) {
        best[j] = score;
        best_cam[j] = static_cast<uint8_t>(c);
        best_u[j] = u[j];
        best_v[j] = v[j];
      }
    }
  }
  for (size_t j = 0; j < len; ++j) {
    uint8_t& flags = cloud.flags[begin + j];
    if (flags & cloud_flags::kSelf) continue;
    if (best_cam[j] == kNoCamera) {
      if (hidden[j]) flags |= cloud_flags::kOccluded;
      continue;
    }
    float rgb[3];
    cloud_internal::sample(input.images[best_cam[j]], best_u[j], best_v[j], rgb);
    cloud.rgb[begin + j] = {cloud_internal::to_byte(rgb[0]), cloud_internal::to_byte(rgb[1]),
                            cloud_internal::to_byte(rgb[2])};
    cloud.camera[begin + j] = best_cam[j];
    flags |= cloud_flags::kColoured;
  }
}

}  // namespace omniview
