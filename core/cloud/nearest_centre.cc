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
    // Locals for everything the loop reads: its byte stores could alias any of it.
    const CentreScore centre = s.centre;
    const float inv_cell = pass.inv_cell, offset = pass.offset;
    const size_t cols = static_cast<size_t>(pass.cols);
    const float* __restrict occluder = options.occlusion ? pass.occluder.data() : nullptr;
    const auto camera = static_cast<uint8_t>(c);
    float* __restrict best_score = best.score.data();
    float* __restrict best_u = best.u.data();
    float* __restrict best_v = best.v.data();
    uint8_t* __restrict best_cam = best.cam.data();
    uint8_t* __restrict hidden = best.hidden.data();
    for (const cloud_internal::Seen& seen : pass.seen) {
      const auto [first, last] = seen.span(begin, end);
      const uint32_t* __restrict index = seen.index.get();
      const float* __restrict seen_u = seen.u.get();
      const float* __restrict seen_v = seen.v.get();
      const float* __restrict seen_range = seen.range.get();
      for (size_t k = first; k < last; ++k) {
        const size_t j = index[k] - begin;
        const float u = seen_u[k], v = seen_v[k];
        const float score = centre(u, v);
        // The depth test only where this camera would win: a point some camera already
        // colours is never flagged hidden, so a losing camera need not look.
        if (score < best_score[j]) {
          if (occluder) {  // as CameraPass::occluder_at
            const float nearest = occluder[size_t(static_cast<int>(v * inv_cell + offset)) * cols +
                                           static_cast<int>(u * inv_cell + offset)];
            if (seen_range[k] > nearest * rel + abs_tol) {
              hidden[j] = 1;
              continue;
            }
          }
          best_score[j] = score;
          best_cam[j] = camera;
          best_u[j] = u;
          best_v[j] = v;
        }
      }
    }
  }
  ColourStats stats;
  uint8_t* __restrict flags_out = cloud.flags.data() + begin;
  uint8_t* __restrict camera_out = cloud.camera.data() + begin;
  PointCloud::Rgb* __restrict rgb_out = cloud.rgb.data() + begin;
  const float* __restrict best_u = best.u.data();
  const float* __restrict best_v = best.v.data();
  const uint8_t* __restrict best_cam = best.cam.data();
  const uint8_t* __restrict hidden = best.hidden.data();
  for (size_t j = 0; j < len; ++j) {
    uint8_t flags = flags_out[j] & static_cast<uint8_t>(~(cloud_flags::kColoured | cloud_flags::kOccluded));
    uint8_t camera = kNoCamera;
    if (flags & cloud_flags::kSelf) {
      ++stats.self_filtered;
    } else if (best_cam[j] == kNoCamera) {
      if (hidden[j]) {
        flags |= cloud_flags::kOccluded;
        ++stats.occluded;
      } else {
        ++stats.unseen;
      }
    } else {
      float rgb[3];
      cloud_internal::sample(input.images[best_cam[j]], best_u[j], best_v[j], rgb);
      rgb_out[j] = {cloud_internal::to_byte(rgb[0]), cloud_internal::to_byte(rgb[1]), cloud_internal::to_byte(rgb[2])};
      camera = best_cam[j];
      flags |= cloud_flags::kColoured;
      ++stats.coloured;
    }
    flags_out[j] = flags;
    camera_out[j] = camera;
  }
  return stats;
}

}  // namespace omniview
