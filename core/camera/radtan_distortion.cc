#include "core/camera/radtan_distortion.h"

#include <algorithm>
#include <cmath>

namespace omniview {

namespace {

// Newton on the full distortion from (mx, my). Tolerances are relative to the distorted
// radius: far out (r ~ 1e4) an absolute 1e-13 is below the spacing of doubles.
bool newton(const RadtanDistortion& d, double dx, double dy, double& mx, double& my) {
  const double scale2 = std::max(1.0, dx * dx + dy * dy);
  for (int iter = 0; iter < 30; ++iter) {
    double fx, fy;
    d.distort(mx, my, fx, fy);
    const double ex = fx - dx, ey = fy - dy;
    if (ex * ex + ey * ey < 1e-26 * scale2) return true;
    // Jacobian of distort() at (mx, my).
    const double x2 = mx * mx, y2 = my * my, r2 = x2 + y2;
    const double radial = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const double dradial = d.k1 + r2 * (2 * d.k2 + 3 * d.k3 * r2);  // d radial / d r2
    const double j00 = radial + 2 * x2 * dradial + 2 * d.p1 * my + 6 * d.p2 * mx;
    const double j01 = 2 * mx * my * dradial + 2 * d.p1 * mx + 2 * d.p2 * my;
    const double j10 = 2 * mx * my * dradial + 2 * d.p1 * mx + 2 * d.p2 * my;
    const double j11 = radial + 2 * y2 * dradial + 6 * d.p1 * my + 2 * d.p2 * mx;
    const double det = j00 * j11 - j01 * j10;
    if (std::abs(det) < 1e-15) return false;
    mx -= (j11 * ex - j01 * ey) / det;
    my -= (-j10 * ex + j00 * ey) / det;
    if (!std::isfinite(mx) || !std::isfinite(my)) return false;
  }
  double fx, fy;
  d.distort(mx, my, fx, fy);
  return (fx - dx) * (fx - dx) + (fy - dy) * (fy - dy) < 1e-18 * scale2;
}

}  // namespace

bool RadtanDistortion::undistort(double dx, double dy, double& mx, double& my) const {
  return undistort(dx, dy, mx, my, max_radius());
}

bool RadtanDistortion::undistort(double dx, double dy, double& mx, double& my, double max_r) const {
  mx = dx;
  my = dy;
  if (is_zero()) return true;
  // Newton from the distorted point itself: right for every pixel of a real image, and
  // near the fold it approaches from inside, where the solution the models accept lies.
  if (newton(*this, dx, dy, mx, my) && mx * mx + my * my <= max_r * max_r) return true;
  // Far out it creeps: with k2 > 0 (EuRoC's calibration, say) a point 84 deg off-axis
  // distorts to r ~ 4000, Newton on the quintic shrinks r by only ~1/5 a step, and pixels
  // of points that project() accepts failed to unproject. Restart from the radial-only
  // inverse: r * radial(r) increases on [0, max_r], so Newton safeguarded by bisection
  // finds it from anywhere.
  const double rd = std::hypot(dx, dy);
  if (rd == 0 || (k1 == 0 && k2 == 0 && k3 == 0)) return false;
  const auto g = [&](double r) {
    const double r2 = r * r;
    return r * (1 + r2 * (k1 + r2 * (k2 + r2 * k3)));
  };
  const auto dg = [&](double r) {
    const double r2 = r * r;
    return 1 + r2 * (3 * k1 + r2 * (5 * k2 + r2 * 7 * k3));
  };
  if (!(g(max_r) > rd)) return false;  // beyond the image of the monotonic range
  double lo = 0, hi = max_r, r = std::min(rd, max_r);
  for (int iter = 0; iter < 100; ++iter) {
    const double f = g(r) - rd;
    if (f == 0) break;
    (f > 0 ? hi : lo) = r;
    double next = r - f / dg(r);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // NaN too (dg = 0 at the fold)
    const bool done = std::abs(next - r) <= 1e-15 * next || hi - lo <= 1e-15 * hi;
    r = next;
    if (done) break;
  }
  mx = dx * r / rd;
  my = dy * r / rd;
  return newton(*this, dx, dy, mx, my);
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
