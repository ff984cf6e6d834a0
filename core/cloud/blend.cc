// Phase 2 of CloudColourer::colour for feathered-blend fusion: each point takes the
// weighted mean of the cameras that see it unhidden, weights from each camera's feather.
#include <limits>

#include "core/cloud/colourer_internal.h"
#include "core/rig/camera_index.h"

namespace omniview {

namespace {

// Per-thread scratch for one chunk of points: the weighted sums so far.
struct Sums {
  std::vector<float> weight, r, g, b, heaviest;
  std::vector<uint8_t> cam, hidden;
  void reset(size_t len) {
    for (auto* a : {&weight, &r, &g, &b, &heaviest}) a->assign(len, 0.f);
    cam.assign(len, kNoCamera);
    hidden.assign(len, 0);
  }
};

}  // namespace

// Camera by camera over points [begin, end), each camera over only the points it sees.
// Each point's sums add the cameras in rig order, as the point-by-point loop did.
ColourStats CloudColourer::blend(PointCloud& cloud, const CameraImages& input, const ColourOptions& options,
                                 size_t begin, size_t end) const {
  const size_t len = end - begin;
  thread_local Sums sums;
  sums.reset(len);
  const float rel = 1.f + options.occlusion_tolerance_rel, abs_tol = options.occlusion_tolerance_m;
  for (size_t c = 0; c < passes_.size(); ++c) {
    const CameraPass& pass = passes_[c];
    if (!pass.active) continue;
    const cv::Mat& feather = cameras_[c]->feather;
    for (const cloud_internal::Seen& seen : pass.seen) {
      const auto [first, last] = seen.span(begin, end);
      for (size_t k = first; k < last; ++k) {
        const size_t j = seen.index[k] - begin;
        const float u = seen.u[k], v = seen.v[k];
        if (options.occlusion && seen.range[k] > pass.occluder_at(u, v) * rel + abs_tol) {
          sums.hidden[j] = 1;
          continue;
        }
        const float w = feather.at<float>(static_cast<int>(v + 0.5f), static_cast<int>(u + 0.5f));
        if (w <= 0) continue;
        float rgb[3];
        cloud_internal::sample(input.images[c], u, v, rgb);
        sums.weight[j] += w;
        sums.r[j] += w * rgb[0];
        sums.g[j] += w * rgb[1];
        sums.b[j] += w * rgb[2];
        if (w > sums.heaviest[j]) {  // the first of equally heavy cameras, as for nearest-centre
          sums.heaviest[j] = w;
          sums.cam[j] = static_cast<uint8_t>(c);
        }
      }
    }
  }
  ColourStats stats;
  for (size_t j = 0; j < len; ++j) {
    uint8_t flags = cloud.flags[begin + j] & static_cast<uint8_t>(~(cloud_flags::kColoured | cloud_flags::kOccluded));
    uint8_t camera = kNoCamera;
    if (flags & cloud_flags::kSelf) {
      ++stats.self_filtered;
    } else if (sums.cam[j] == kNoCamera) {
      if (sums.hidden[j]) {
        flags |= cloud_flags::kOccluded;
        ++stats.occluded;
      } else {
        ++stats.unseen;
      }
    } else {
      const float w = sums.weight[j];
      cloud.rgb[begin + j] = {cloud_internal::to_byte(sums.r[j] / w), cloud_internal::to_byte(sums.g[j] / w),
                              cloud_internal::to_byte(sums.b[j] / w)};
      camera = sums.cam[j];
      flags |= cloud_flags::kColoured;
      ++stats.coloured;
    }
    cloud.flags[begin + j] = flags;
    cloud.camera[begin + j] = camera;
  }
  return stats;
}

}  // namespace omniview
