#include "core/camera/omni_radtan.h"

#include <cmath>

namespace omniview {

OmniRadtan::OmniRadtan(double xi, double fu, double fv, double pu, double pv,
                       const RadtanDistortion& d)
    : xi_(xi), fu_(fu), fv_(fv), pu_(pu), pv_(pv), dist_(d) {
  w_ = xi_ <= 1 ? xi_ : 1 / xi_;
  // Without distortion nothing folds: the limit is the geometric one alone (max_radius()
  // would cap |m| at 1000 and cut off points that are imageable, if far outside the image).
  const double r = dist_.max_radius();
  max_r2_ = dist_.is_zero() ? INFINITY : r * r;
}

bool OmniRadtan::unproject(double u, double v, Eigen::Vector3d& ray) const {
  double mx, my;
  if (!dist_.undistort((u - pu_) / fu_, (v - pv_) / fv_, mx, my, std::sqrt(max_r2_))) return false;
  const double r2 = mx * mx + my * my;
  if (r2 > max_r2_) return false;
  const double disc = 1 + (1 - xi_ * xi_) * r2;
  if (disc < 0) return false;
  const double factor = (xi_ + std::sqrt(disc)) / (1 + r2);
  ray = Eigen::Vector3d(factor * mx, factor * my, factor - xi_);
  if (ray.z() <= -w_ * ray.norm()) return false;
  ray.normalize();
  return true;
}

}  // namespace omniview
