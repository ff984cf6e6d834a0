// A depth image registered to a camera (the same size and intrinsics: each pixel's value is
// the depth, along the optical axis, of what that pixel sees) as points in the camera's
// optical frame. Robots' depth cameras deliver this (Spot's `*_depth_in_visual_frame`); the
// per-pixel unprojection is here, in an optimised library, because a frame set carries five
// such images and the daemon turns every one into points.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "core/camera/camera.h"

namespace omniview {

struct DepthImage {
  std::span<const uint8_t> data;  // camera.width x camera.height 16-bit values, little-endian
  double scale = 1000;            // metres = value / scale; value 0: nothing measured
};

// Points from every `step`-th pixel each way (step < 1: 1) that holds a depth of at most
// `max_range_m`. The caller has checked that `image.data` holds 2 bytes per pixel of
// `camera` and that the scale is positive and finite (std::invalid_argument otherwise).
std::vector<Eigen::Vector3f> depth_image_points(const DepthImage& image, const Camera& camera, int step,
                                                double max_range_m);

}  // namespace omniview
