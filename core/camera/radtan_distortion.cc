#include "core/camera/radtan_distortion.h"

#include <cmath>

namespace omniview {

bool RadtanDistortion::undistort(double dx, double dy, double& mx, double& my) const {
  mx = dx;
  my = dy;
  if (is_zero()) return true;
  for (int iter = 0; iter < 30; ++iter) {
    double fx, fy;
    distort(mx, my, fx, fy);
    const double ex = fx - dx, ey = fy - dy;
    if (ex * ex + ey * ey < 1e-26) return true;
    // Jacobian of distort() at (mx, my).
    const double x2 = mx * mx, y2 = my * my, r2 = x2 + y2;
    const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double dradial = k1 + r2 * (2 * k2 + 3 * k3 * r2);  // d radial / d r2
    const double j00 = radial + 2 * x2 * dradial + 2 * p1 * my + 6 * p2 * mx;
    const double j01 = 2 * mx * my * dradial + 2 * p1 * mx + 2 * p2 * my;
    const double j10 = 2 * mx * my * dradial + 2 * p1 * mx + 2 * p2 * my;
    const double j11 = radial + 2 * y2 * dradial + 6 * p1 * my + 2 * p2 * mx;
    const double det = j00 * j11 - j01 * j10;
    if (std::abs(det) < 1e-15) return false;
    mx -= (j11 * ex - j01 * ey) / det;
    my -= (-j10 * ex + j00 * ey) / det;
    if (!std::isfinite(mx) || !std::isfinite(my)) return false;
  }
  double fx, fy;
  distort(mx, my, fx, fy);
  return std::hypot(fx - dx, fy - dy) < 1e-9;
}

double RadtanDistortion::max_radius(double cap) const {
  // d/dr [r (1 + k1 r^2 + k2 r^4 + k3 r^6)] = 1 + 3 k1 r^2 + 5 k2 r^4 + 7 k3 r^6
  const auto slope = [&](double r) {
    const double r2 = r * r;
    return 1 + r2 * (3 * k1 + r2 * (5 * k2 + r2 * 7 * k3));
  };
  if (k1 == 0 && k2 == 0 && k3 == 0) return cap;
  // March outwards in growing steps, then bisect the first sign change.
  double lo = 0, hi = 1e-3;
  while (hi < cap && slope(hi) > 0) {
    lo = hi;
    hi *= 1.05;
  }
  if (hi >= cap) return cap;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (slope(mid) > 0 ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace omniview
