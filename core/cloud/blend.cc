// Phase 2 of CloudColourer::colour for feathered-blend fusion: each point takes the
// weighted mean of the cameras that see it unhidden, weights from each camera's feather.
#include <limits>

#include "core/cloud/colourer_internal.h"
#include "core/rig/camera_index.h"

namespace omniview {

void CloudColourer::blend(PointCloud& cloud, const CameraImages& input, const ColourOptions& options, size_t begin,
                          size_t end) const {
  const float rel = 1.f + options.occlusion_tolerance_rel, abs_tol = options.occlusion_tolerance_m;
  const size_t n_cams = passes_.size();
  for (size_t i = begin; i < end; ++i) {
    uint8_t& flags = cloud.flags[i];
    if (flags & cloud_flags::kSelf) continue;
    bool hidden = false;
    uint8_t best_cam = kNoCamera;
    float heaviest = 0, sum_w = 0, sum[3] = {0, 0, 0};
    for (size_t c = 0; c < n_cams; ++c) {
      const CameraPass& pass = passes_[c];
      if (!pass.active || !(pass.valid[i] & 1)) continue;
      const float u = pass.u[i], v = pass.v[i];
      if (options.occlusion) {
        const int cx = static_cast<int>(u * pass.inv_cell + pass.offset);
        const int cy = static_cast<int>(v * pass.inv_cell + pass.offset);
        if (pass.range[i] > pass.occluder[size_t(cy) * pass.cols + cx] * rel + abs_tol) {
          hidden = true;
          continue;
        }
      }
      const float w = cameras_[c]->feather.at<float>(static_cast<int>(v + 0.5f), static_cast<int>(u + 0.5f));
      if (w <= 0) continue;
      float rgb[3];
      cloud_internal::sample(input.images[c], u, v, rgb);
      sum_w += w;
      for (int k = 0; k < 3; ++k) sum[k] += w * rgb[k];
      if (w > heaviest) {  // the first of equally heavy cameras, as for nearest-centre
        heaviest = w;
        best_cam = static_cast<uint8_t>(c);
      }
    }
    if (best_cam == kNoCamera) {
      if (hidden) flags |= cloud_flags::kOccluded;
      continue;
    }
    float rgb[3];
    for (int k = 0; k < 3; ++k) rgb[k] = sum[k] / sum_w;
    cloud.rgb[i] = {cloud_internal::to_byte(rgb[0]), cloud_internal::to_byte(rgb[1]), cloud_internal::to_byte(rgb[2])};
    cloud.camera[i] = best_cam;
    flags |= cloud_flags::kColoured;
  }
}

}  // namespace omniview
