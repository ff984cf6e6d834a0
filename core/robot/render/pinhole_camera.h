// The virtual pinhole a robot layer is rendered from: a view's intrinsics and image size.
//
// Pixel centres at integer coordinates (OpenCV): pixel (u, v) covers [u-0.5, u+0.5] x
// [v-0.5, v+0.5] and a point p in the optical frame lands at (fx px/pz + cx, fy py/pz + cy).
#pragma once

#include "core/geometry/pose.h"
#include "core/view/view_spec.h"

namespace omniview::robot {

struct PinholeCamera {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;

  bool operator==(const PinholeCamera&) const = default;
  // Pixel of a point in the optical frame (z > 0 assumed).
  Vec2 project(const Vec3& p_optical) const { return {fx * p_optical.x() / p_optical.z() + cx, fy * p_optical.y() / p_optical.z() + cy}; }
};

// The pinhole of a perspective or bird's-eye view (README, "Conventions"): square pixels,
// f = (W/2)/tan(hfov/2), principal point ((W-1)/2, (H-1)/2).
PinholeCamera pinhole_camera_of(const ViewSpec& spec);

// Pose of the view's optical frame (z forward, x right, y down) in the view's `frame`. For
// a view given in the robot's base frame this is the renderer's T_robot_camera.
Pose T_frame_optical(const ViewSpec& spec);

}  // namespace omniview::robot
