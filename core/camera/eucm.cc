#include "core/camera/eucm.h"

#include <cmath>

namespace omniview {

Eucm::Eucm(double alpha, double beta, double fu, double fv, double pu, double pv)
    : alpha_(alpha), beta_(beta), fu_(fu), fv_(fv), pu_(pu), pv_(pv) {
  w_ = alpha_ <= 0.5 ? alpha_ / (1 - alpha_) : (1 - alpha_) / alpha_;
}

bool Eucm::unproject(double u, double v, Eigen::Vector3d& ray) const {
  const double mx = (u - pu_) / fu_, my = (v - pv_) / fv_;
  const double r2 = mx * mx + my * my;
  const double gamma = 1 - alpha_;
  if (alpha_ > 0.5 && r2 > 1 / (beta_ * (2 * alpha_ - 1))) return false;
  const double mz = (1 - beta_ * alpha_ * alpha_ * r2) /
                    (alpha_ * std::sqrt(1 - (2 * alpha_ - 1) * beta_ * r2) + gamma);
  ray = Eigen::Vector3d(mx, my, mz);
  const double rho = std::sqrt(beta_ * r2 + mz * mz);
  if (!(mz > -w_ * rho)) return false;
  ray.normalize();
  return true;
}

}  // namespace omniview
