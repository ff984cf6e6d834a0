#include "core/map/usable_region.h"

#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/map/parallel_rows.h"

namespace omniview {

cv::Mat usable_region(const Camera& cam) {
  // Unprojection is iterative for some models: evaluate it on a 4 px grid and fill in.
  // The region's edge is then good to ~2 px, plenty for a feathering weight.
  constexpr int kStep = 4;
  const int gw = (cam.width + kStep - 1) / kStep, gh = (cam.height + kStep - 1) / kStep;
  cv::Mat grid(gh, gw, CV_8UC1);
  const double cos_half_fov = cam.fov_deg > 0 ? std::cos(cam.fov_deg * M_PI / 360) : -2.0;
  parallel_rows(cv::Range(0, gh), [&](const cv::Range& rows) {
    for (int gy = rows.start; gy < rows.end; ++gy) {
      for (int gx = 0; gx < gw; ++gx) {
        Eigen::Vector3d ray;
        const bool ok = unproject(cam.model, Eigen::Vector2d(gx * kStep + (kStep - 1) / 2.0, gy * kStep + (kStep - 1) / 2.0), ray) &&
                        ray.normalized().z() >= cos_half_fov;
        grid.at<uint8_t>(gy, gx) = ok ? 255 : 0;
      }
    }
  });
  cv::Mat region;
  cv::resize(grid, region, cv::Size(gw * kStep, gh * kStep), 0, 0, cv::INTER_NEAREST);
  region = region(cv::Rect(0, 0, cam.width, cam.height)).clone();
  if (!cam.mask.empty()) region &= (cam.mask > 127);
  return region;
}

cv::Mat feather_weights(const Camera& cam, double feather_px) {
  cv::Mat padded;
  // A zero border so the image edge counts as the region's edge.
  cv::copyMakeBorder(usable_region(cam), padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::Mat distance;
  cv::distanceTransform(padded, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::Mat weights = distance(cv::Rect(1, 1, cam.width, cam.height)) * (1.0 / feather_px);
  cv::min(weights, 1.0, weights);
  return weights;
}

bool FeatherSet::fits(const Rig& rig, double feather) const {
  const auto& cameras = rig.cameras();
  if (feather != feather_px || weights.size() != cameras.size()) return false;
  for (size_t i = 0; i < cameras.size(); ++i) {
    if (weights[i].type() != CV_32FC1 || weights[i].cols != cameras[i].width || weights[i].rows != cameras[i].height) {
      return false;
    }
  }
  return true;
}

FeatherSet feather_set(const Rig& rig, double feather_px) {
  FeatherSet set;
  set.feather_px = feather_px;
  for (const Camera& cam : rig.cameras()) set.weights.push_back(feather_weights(cam, feather_px));
  return set;
}

}  // namespace omniview
