// A calibrated camera: model, image size, optional mask, and where it sits.
#pragma once

#include <string>

#include <opencv2/core/mat.hpp>

#include "core/camera/camera_model.h"
#include "core/geometry/pose.h"

namespace omniview {

struct Camera {
  std::string name;    // also its frame's name in the rig's frame graph
  int width = 0;       // image size the calibration is for
  int height = 0;
  CameraModel model{PinholeRadtan(1, 1, 0, 0)};
  cv::Mat mask;        // optional CV_8UC1 of width x height; > 127 = usable pixel
  // Optional limit on the lens' field of view (full angle, degrees; 0 = the model's own
  // limit). A 210 deg fisheye's Kannala-Brandt polynomial often stays monotonic well past
  // what the lens sees, and the image outside its circle is black.
  double fov_deg = 0;
  std::string parent_frame;
  Pose T_parent_cam = Pose::Identity();

  // Pixel centres are at integer coordinates, so bilinear sampling needs 0 <= u <= W-1.
  bool in_image(double u, double v) const { return u >= 0 && v >= 0 && u <= width - 1 && v <= height - 1; }
};

}  // namespace omniview
