#include "core/camera/pinhole_radtan.h"

namespace omniview {

PinholeRadtan::PinholeRadtan(double fu, double fv, double pu, double pv, const RadtanDistortion& d)
    : fu_(fu), fv_(fv), pu_(pu), pv_(pv), dist_(d) {
  const double r = dist_.max_radius();
  max_r2_ = r * r;
}

bool PinholeRadtan::unproject(double u, double v, Eigen::Vector3d& ray) const {
  double mx, my;
  if (!dist_.undistort((u - pu_) / fu_, (v - pv_) / fv_, mx, my)) return false;
  if (mx * mx + my * my > max_r2_) return false;
  ray = Eigen::Vector3d(mx, my, 1.0).normalized();
  return true;
}

}  // namespace omniview
