#include "core/camera/pinhole_radtan.h"

#include <cmath>

namespace omniview {

PinholeRadtan::PinholeRadtan(double fu, double fv, double pu, double pv, const RadtanDistortion& d)
    : fu_(fu), fv_(fv), pu_(pu), pv_(pv), dist_(d) {
  // Without distortion nothing folds: the limit is the geometric one alone (max_radius()
  // would cap |m| at 1000 and cut off points that are imageable, if far outside the image).
  const double r = dist_.max_radius();
  max_r2_ = dist_.is_zero() ? INFINITY : r * r;
}

bool PinholeRadtan::unproject(double u, double v, Eigen::Vector3d& ray) const {
  double mx, my;
  if (!dist_.undistort((u - pu_) / fu_, (v - pv_) / fv_, mx, my, std::sqrt(max_r2_))) return false;
  if (mx * mx + my * my > max_r2_) return false;
  ray = Eigen::Vector3d(mx, my, 1.0).normalized();
  return true;
}

}  // namespace omniview
