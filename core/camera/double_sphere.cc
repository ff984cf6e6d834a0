#include "core/camera/double_sphere.h"

#include <cmath>

namespace omniview {

DoubleSphere::DoubleSphere(double xi, double alpha, double fu, double fv, double pu, double pv)
    : xi_(xi), alpha_(alpha), fu_(fu), fv_(fv), pu_(pu), pv_(pv) {
  const double w1 = alpha_ <= 0.5 ? alpha_ / (1 - alpha_) : (1 - alpha_) / alpha_;
  w2_ = (w1 + xi_) / std::sqrt(2 * w1 * xi_ + xi_ * xi_ + 1);
}

bool DoubleSphere::unproject(double u, double v, Eigen::Vector3d& ray) const {
  const double mx = (u - pu_) / fu_, my = (v - pv_) / fv_;
  const double r2 = mx * mx + my * my;
  if (alpha_ > 0.5 && r2 > 1 / (2 * alpha_ - 1)) return false;
  const double mz = (1 - alpha_ * alpha_ * r2) /
                    (alpha_ * std::sqrt(1 - (2 * alpha_ - 1) * r2) + 1 - alpha_);
  const double disc = mz * mz + (1 - xi_ * xi_) * r2;
  if (disc < 0) return false;
  const double k = (mz * xi_ + std::sqrt(disc)) / (mz * mz + r2);
  ray = Eigen::Vector3d(k * mx, k * my, k * mz - xi_);
  if (!(ray.z() > -w2_ * ray.norm())) return false;
  ray.normalize();
  return true;
}

}  // namespace omniview
