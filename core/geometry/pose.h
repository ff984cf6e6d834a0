// Rigid transforms and the angle conventions of the API (README, "Conventions").
//
// T_A_B is the pose of frame B in frame A: p_A = T_A_B * p_B.
// Orientation as yaw, pitch, roll (radians here; degrees only at the API edge) with
// R = Rz(yaw) * Ry(pitch) * Rx(roll), as in ROS: positive pitch looks down.
#pragma once

#include <Eigen/Geometry>
#include <string>

namespace omniview {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Pose = Eigen::Isometry3d;

Mat3 rotation_from_ypr(double yaw, double pitch, double roll);

// Inverse of rotation_from_ypr; pitch is in [-pi/2, pi/2].
Eigen::Vector3d ypr_from_rotation(const Mat3& R);

Pose make_pose(const Vec3& translation, double yaw, double pitch, double roll);

// Builds a pose from a 4x4 homogeneous matrix. Rejects matrices that are not rigid
// (rotation not orthonormal within `tolerance`, determinant not +1, last row not 0 0 0 1)
// and re-orthonormalises the rotation so small rounding in calibration files does not
// accumulate through chains. `what` names the matrix in the error message.
Pose pose_from_matrix(const Mat4& m, const std::string& what, double tolerance = 1e-4);

// View frame (REP-103: x forward, y left, z up) to optical frame (z forward, x right,
// y down) of the view's virtual pinhole: p_view = R_view_optical * p_optical.
const Mat3& R_view_optical();

}  // namespace omniview
