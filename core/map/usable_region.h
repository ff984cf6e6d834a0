// Where in a camera's image blending may take it: inside the image, its mask and its
// lens' field of view, with weights that fade to zero towards the edge of that region.
#pragma once

#include <opencv2/core/mat.hpp>

#include <vector>

#include "core/camera/camera.h"
#include "core/rig/rig.h"

namespace omniview {

// CV_8UC1 of the camera's size: 255 where a pixel is usable (its ray exists, lies inside
// fov_deg, and the mask allows it), else 0.
cv::Mat usable_region(const Camera& camera);

// CV_32F of the camera's size: min(1, distance to the region's edge / feather_px).
cv::Mat feather_weights(const Camera& camera, double feather_px);

// Every rig camera's feather_weights for one feather width. A blend map rebuilt at every
// geometry update (a measured-depth view) takes them from here: made anew, the distance
// transforms cost a third of its build.
struct FeatherSet {
  double feather_px = 0;
  std::vector<cv::Mat> weights;  // per rig camera

  // Whether these are the weights a map of `rig`'s cameras with `feather_px` needs.
  bool fits(const Rig& rig, double feather) const;
};
FeatherSet feather_set(const Rig& rig, double feather_px);

}  // namespace omniview
