#include "core/robot/render/pinhole_camera.h"

#include <cmath>
#include <stdexcept>

namespace omniview::robot {

PinholeCamera pinhole_camera_of(const ViewSpec& spec) {
  if (spec.type != ViewType::kPerspective && spec.type != ViewType::kBirdseye) {
    throw std::invalid_argument("view '" + spec.name + "': the robot overlay needs a perspective or birdseye view, not " +
                                to_string(spec.type));
  }
  PinholeCamera c;
  c.width = spec.width;
  c.height = spec.height;
  c.fx = c.fy = (spec.width / 2.0) / std::tan(spec.hfov_deg * M_PI / 360.0);
  c.cx = (spec.width - 1) / 2.0;
  c.cy = (spec.height - 1) / 2.0;
  return c;
}

Pose T_frame_optical(const ViewSpec& spec) {
  Pose T_view_optical = Pose::Identity();
  T_view_optical.linear() = R_view_optical();
  return spec.T_frame_view() * T_view_optical;
}

}  // namespace omniview::robot
