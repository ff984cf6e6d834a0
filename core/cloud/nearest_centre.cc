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

}  // namespace

// Camera by camera over points [begin, end), each camera over only the points it sees (in
// point order, so the chunk's scratch is read in order too); then one pass samples the
// winners. Cameras in rig order, a strictly better score wins: the choice is the one the
// point-by-point loop made.
ColourStats CloudColourer::nearest_centre(PointCloud& cloud, const CameraImages& input, const ColourOptions& options,
                                          size_t begin, size_t end) const {
  const size_t len = end - begin;
  thread_local Best best;
  best.reset(len);
  const float rel = 1.f + options.occlusion_tolerance_rel, abs_tol = options.occlusion_tolerance_m;
  for (size_t c = 0; c < passes_.size(); ++c) {
    const CameraPass& pass = passes_[c];
    if (!pass.active) continue;
    const CameraSetup& s = *cameras_[c];
    for (const cloud_internal::Seen& seen : pass.seen) {
      const auto [first, last] = seen.span(begin, end);
      for (size_t k = first; k < last; ++k) {
        const size_t j = seen.index[k] - begin;
        const float u = seen.u[k], v = seen.v[k];
        const float du = u - s.cx, dv = v - s.cy;
        const float score = (du * du + dv * dv) * s.inv_half_diag2;
        // The depth test only where this camera would win: a point some camera already
        // colours is never flagged hidden, so a losing camera need not look.
        if (score < best.score[j]) {
          if (options.occlusion && seen.range[k] > pass.occluder_at(u, v) * rel + abs_tol) {
            best.hidden[j] = 1;
            continue;
          }
          best.score[j] = score;
          best.cam[j] = static_cast<uint8_t>(c);
          best.u[j] = u;
          best.v[j] = v;
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
    } else if (best.cam[j] == kNoCamera) {
      if (best.hidden[j]) {
        flags |= cloud_flags::kOccluded;
        ++stats.occluded;
      } else {
        ++stats.unseen;
      }
    } else {
      float rgb[3];
      cloud_internal::sample(input.images[best.cam[j]], best.u[j], best.v[j], rgb);
      cloud.rgb[begin + j] = {cloud_internal::to_byte(rgb[0]), cloud_internal::to_byte(rgb[1]),
                              cloud_internal::to_byte(rgb[2])};
      camera = best.cam[j];
      flags |= cloud_flags::kColoured;
      ++stats.coloured;
    }
    cloud.flags[begin + j] = flags;
    cloud.camera[begin + j] = camera;
  }
  return stats;
}

}  // namespace omniview
