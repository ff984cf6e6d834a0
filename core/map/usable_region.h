// Where in a camera's image blending may take it: inside the image, its mask and its
// lens' field of view, with weights that fade to zero towards the edge of that region.
#pragma once

#include <opencv2/core/mat.hpp>

#include "core/camera/camera.h"

namespace omniview {

// CV_8UC1 of the camera's size: 255 where a pixel is usable (its ray exists, lies inside
// fov_deg, and the mask allows it), else 0.
cv::Mat usable_region(const Camera& camera);

// CV_32F of the camera's size: min(1, distance to the region's edge / feather_px).
cv::Mat feather_weights(const Camera& camera, double feather_px);

}  // namespace omniview
