#include "core/geometry/pose.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace omniview {

Mat3 rotation_from_ypr(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
          Eigen::AngleAxisd(roll, Vec3::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d ypr_from_rotation(const Mat3& R) {
  // cos(pitch) from the first column rather than asin(-R20): near +-90 deg asin loses half
  // the digits (1e-8 rad), and |R20| < 1 - 1e-12 switched to the gimbal-lock branch (which
  // drops roll) up to 1.4e-6 rad away from the lock.
  const double cos_pitch = std::hypot(R(0, 0), R(1, 0));
  const double pitch = std::atan2(-R(2, 0), cos_pitch);
  double yaw, roll;
  if (cos_pitch > 1e-8) {  // ~sqrt(eps): below it the entries are mostly rounding noise
    yaw = std::atan2(R(1, 0), R(0, 0));
    roll = std::atan2(R(2, 1), R(2, 2));
  } else {  // gimbal lock: only yaw - roll (or yaw + roll) is defined; put it all in yaw
    yaw = std::atan2(-R(0, 1), R(1, 1));
    roll = 0.0;
  }
  return {yaw, pitch, roll};
}

Pose make_pose(const Vec3& translation, double yaw, double pitch, double roll) {
  Pose T = Pose::Identity();
  T.linear() = rotation_from_ypr(yaw, pitch, roll);
  T.translation() = translation;
  return T;
}

Pose pose_from_matrix(const Mat4& m, const std::string& what, double tolerance) {
  if (!m.allFinite()) throw std::invalid_argument(what + ": transform has non-finite entries");
  const Eigen::RowVector4d last = m.row(3);
  if ((last - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9) {
    std::ostringstream os;
    os << what << ": last row of a rigid transform must be [0, 0, 0, 1], got [" << last << "]";
    throw std::invalid_argument(os.str());
  }
  const Mat3 R = m.topLeftCorner<3, 3>();
  const double orthonormality_error = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (orthonormality_error > tolerance || R.determinant() < 0) {
    std::ostringstream os;
    os << what << ": rotation part is not a rotation (|R^T R - I| = " << orthonormality_error
       << ", det = " << R.determinant() << "); a rigid transform is required";
    throw std::invalid_argument(os.str());
  }
  Pose T = Pose::Identity();
  T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T.translation() = m.topRightCorner<3, 1>();
  return T;
}

const Mat3& R_view_optical() {
  // Columns: optical x (right) = view -y, optical y (down) = view -z, optical z = view x.
  static const Mat3 R = (Mat3() << 0, 0, 1, -1, 0, 0, 0, -1, 0).finished();
  return R;
}

}  // namespace omniview
