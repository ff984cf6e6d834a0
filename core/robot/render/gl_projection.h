// The OpenGL projection that reproduces a pinhole camera pixel for pixel.
//
// It takes points in the camera's optical frame (z forward, x right, y down; no GL-style
// -z camera) to clip coordinates, such that after the viewport transform of a W x H
// viewport the window coordinates of a point are (u + 0.5, v + 0.5), with (u, v) its
// OpenCV pixel: GL samples pixel centres at half-integer window coordinates, OpenCV puts
// them at integers. v is not flipped: window row y is image row v, so a colour buffer
// whose first row is window row 0 (OSMesa's default) is the image in OpenCV row order.
// This mirrors the picture relative to GL's convention, so front faces are clockwise.
#pragma once

#include <Eigen/Core>

#include "core/robot/render/pinhole_camera.h"

namespace omniview::robot {

// Depth maps z = near to -1 and z = far to +1 in normalised device coordinates.
Eigen::Matrix4d gl_projection(const PinholeCamera& camera, double near, double far);

}  // namespace omniview::robot
