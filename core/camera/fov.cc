#include "core/camera/fov.h"

#include <cmath>
#include <stdexcept>

namespace omniview {

Fov::Fov(double fu, double fv, double pu, double pv, double w)
    : fu_(fu), fv_(fv), pu_(pu), pv_(pv), w_(w), two_tan_half_w_(2 * std::tan(w / 2)) {}

bool Fov::unproject(double u, double v, Eigen::Vector3d& ray) const {
  const double mx = (u - pu_) / fu_, my = (v - pv_) / fv_;
  const double rd = std::hypot(mx, my);
  if (rd < 1e-12) {
    ray = Eigen::Vector3d::UnitZ();
    return true;
  }
  if (rd * w_ >= M_PI_2) return false;  // beyond the model's 90 deg half-angle
  const double r = std::tan(rd * w_) / two_tan_half_w_;
  ray = Eigen::Vector3d(mx * r / rd, my * r / rd, 1.0).normalized();
  return true;
}

}  // namespace omniview
