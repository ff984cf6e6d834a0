// Phase 2 of CloudColourer::colour for nearest-centre fusion: each point takes the camera
// whose pixel is nearest its image centre among those that see it unhidden.
#include <algorithm>
#include <limits>

#include "core/cloud/colourer_internal.h"
#include "core/rig/camera_index.h"

namespace omniview {
namespace {

struct Votes {  // the best camera so far for each point of a chunk
  float* best;
  float* best_u;
  float* best_v;
  uint8_t* best_cam;
  uint8_t* hidden;
};

// One camera's vote on the points of [begin, begin + len) it sees (`seen`, ascending; a
// camera sees a fraction of the cloud, so walking its list beats testing every point).
void vote(const std::vector<uint32_t>& seen, size_t begin, size_t len, const float* u, const float* v,
          const float* range, const cv::Mat* occluder, float inv_cell, float offset, float rel, float abs_tol,
          float cx, float cy, float inv_half_diag2, uint8_t cam, const Votes& out) {
  const auto end = static_cast<uint32_t>(begin + len);
  for (auto it = std::lower_bound(seen.begin(), seen.end(), static_cast<uint32_t>(begin));
       it != seen.end() && *it < end; ++it) {
    const uint32_t i = *it;
    const size_t j = i - begin;
    if (occluder) {
      const float nearest = occluder->ptr<float>(static_cast<int>(v[i] * inv_cell + offset))
                                [static_cast<int>(u[i] * inv_cell + offset)];
      if (range[i] > nearest * rel + abs_tol) {
        out.hidden[j] = 1;
        continue;
      }
    }
    const float du = u[i] - cx, dv = v[i] - cy;
    const float score = (du * du + dv * dv) * inv_half_diag2;
    if (score < out.best[j]) {  // strictly better: rig order breaks ties
      out.best[j] = score;
      out.best_cam[j] = cam;
      out.best_u[j] = u[i];
      out.best_v[j] = v[i];
    }
  }
}

}  // namespace

// Camera by camera, each walking the points it sees in order; the per-point choice is as in
// a point-by-point loop over cameras in rig order.
void CloudColourer::nearest_centre(PointCloud& cloud, const CameraImages& input, const ColourOptions& options,
                                   size_t begin, size_t end) const {
  const size_t len = end - begin;
  std::vector<float> best(len, std::numeric_limits<float>::max()), best_u(len), best_v(len);
  std::vector<uint8_t> best_cam(len, kNoCamera), hidden(len, 0);
  const Votes votes{best.data(), best_u.data(), best_v.data(), best_cam.data(), hidden.data()};
  const float rel = 1.f + options.occlusion_tolerance_rel, abs_tol = options.occlusion_tolerance_m;
  for (size_t c = 0; c < passes_.size(); ++c) {
    const CameraPass& pass = passes_[c];
    if (!pass.active) continue;
    const CameraSetup& s = *cameras_[c];
    vote(pass.seen, begin, len, pass.u.data(), pass.v.data(), pass.range.data(),
         options.occlusion ? &pass.occluder : nullptr, pass.inv_cell, pass.offset, rel, abs_tol, s.cx, s.cy,
         s.inv_half_diag2, static_cast<uint8_t>(c), votes);
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
