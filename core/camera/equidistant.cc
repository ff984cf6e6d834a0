#include "core/camera/equidistant.h"

#include <algorithm>
#include <cmath>

namespace omniview {

Equidistant::Equidistant(double fu, double fv, double pu, double pv, double k1, double k2,
                         double k3, double k4)
    : fu_(fu), fv_(fv), pu_(pu), pv_(pv), k1_(k1), k2_(k2), k3_(k3), k4_(k4) {
  // d'(theta) = 1 + 3 k1 t^2 + 5 k2 t^4 + 7 k3 t^6 + 9 k4 t^8; find its first zero in (0, pi].
  const auto slope = [&](double t) {
    const double t2 = t * t;
    return 1 + t2 * (3 * k1_ + t2 * (5 * k2_ + t2 * (7 * k3_ + t2 * 9 * k4_)));
  };
  max_theta_ = M_PI;
  double lo = 0;
  // Steps of 1e-3 up to and including pi itself (an accumulated t += 1e-3 stops short of
  // it and would miss a turn in the last partial step).
  for (int i = 1; lo < M_PI; ++i) {
    const double t = std::min(i * 1e-3, M_PI);
    if (slope(t) <= 0) {
      double hi = t;
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (slope(mid) > 0 ? lo : hi) = mid;
      }
      max_theta_ = lo;
      break;
    }
    lo = t;
  }
}

double Equidistant::distorted_angle(double theta) const {
  const double t2 = theta * theta;
  return theta * (1 + t2 * (k1_ + t2 * (k2_ + t2 * (k3_ + t2 * k4_))));
}

bool Equidistant::unproject(double u, double v, Eigen::Vector3d& ray) const {
  const double mx = (u - pu_) / fu_, my = (v - pv_) / fv_;
  const double d = std::hypot(mx, my);
  if (d < 1e-15) {
    ray = Eigen::Vector3d::UnitZ();
    return true;
  }
  if (d > distorted_angle(max_theta_)) return false;
  // Newton on distorted_angle(theta) = d; d is monotonic on [0, max_theta].
  double theta = std::min(d, max_theta_);
  for (int iter = 0; iter < 50; ++iter) {
    const double t2 = theta * theta;
    const double f = distorted_angle(theta) - d;
    const double df = 1 + t2 * (3 * k1_ + t2 * (5 * k2_ + t2 * (7 * k3_ + t2 * 9 * k4_)));
    const double step = f / df;
    theta = std::clamp(theta - step, 0.0, max_theta_);
    if (std::abs(step) < 1e-14) break;
  }
  if (std::abs(distorted_angle(theta) - d) > 1e-9) return false;
  const double s = std::sin(theta) / d;
  ray = Eigen::Vector3d(mx * s, my * s, std::cos(theta));
  return true;
}

}  // namespace omniview
