// Realistic calibrations of every supported model, each with the edge of its field of view
// worked out here from the model's published validity condition (not read back from the
// code under test), so round-trip tests can sweep the whole field and probe its edge.
#pragma once

#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "core/camera/camera_model.h"
#include "test_support.h"

namespace omniview::testing {

// First zero in (0, hi] of an increasing-then-turning slope function, by scanning and
// bisection; `hi` if it never turns.
template <typename F>
double first_zero(F slope, double hi) {
  const int steps = 20000;
  double lo = 0;
  for (int i = 1; i <= steps; ++i) {
    const double t = hi * i / steps;
    if (slope(t) <= 0) {
      double a = lo, b = t;
      for (int k = 0; k < 100; ++k) ((slope(0.5 * (a + b)) > 0) ? a : b) = 0.5 * (a + b);
      return a;
    }
    lo = t;
  }
  return hi;
}

// Normalised radius where r (1 + k1 r^2 + k2 r^4 + k3 r^6) stops increasing. A polynomial
// that never turns is capped at |m| = 1000 (RadtanDistortion::max_radius's default: a
// thousand focal lengths off the image); no distortion at all has no limit.
inline double radtan_fold_radius(const RadtanDistortion& d) {
  if (d.is_zero()) return INFINITY;
  const auto slope = [&](double r) {
    const double r2 = r * r;
    return 1 + 3 * d.k1 * r2 + 5 * d.k2 * r2 * r2 + 7 * d.k3 * r2 * r2 * r2;
  };
  return first_zero(slope, 1000.0);
}

// Kannala-Brandt: theta where d(theta) stops increasing, or pi.
inline double kb_max_theta(double k1, double k2, double k3, double k4) {
  return first_zero(
      [&](double t) {
        const double t2 = t * t;
        return 1 + 3 * k1 * t2 + 5 * k2 * t2 * t2 + 7 * k3 * t2 * t2 * t2 + 9 * k4 * t2 * t2 * t2 * t2;
      },
      M_PI);
}

// Mei: z > -w |p| with w = xi (xi <= 1) or 1/xi (beyond, the sphere's horizon seen from
// the projection centre), and the distorted radius m = sin t / (cos t + xi) inside the fold.
inline double omni_max_theta(double xi, const RadtanDistortion& d) {
  const double horizon = std::acos(-(xi <= 1 ? xi : 1 / xi));
  const double fold = radtan_fold_radius(d);
  if (!std::isfinite(fold)) return horizon;
  // m(theta) increases up to the horizon, so bisect m(theta) = fold on [0, horizon].
  const auto m = [&](double t) { return std::sin(t) / (std::cos(t) + xi); };
  if (m(horizon * (1 - 1e-12)) <= fold) return horizon;
  double a = 0, b = horizon;
  for (int k = 0; k < 100; ++k) ((m(0.5 * (a + b)) < fold) ? a : b) = 0.5 * (a + b);
  return a;
}

// Double sphere (Usenko et al. 2018, eq. 43-45): z > -w2 d1.
inline double ds_w2(double xi, double alpha) {
  const double w1 = alpha <= 0.5 ? alpha / (1 - alpha) : (1 - alpha) / alpha;
  return (w1 + xi) / std::sqrt(2 * w1 * xi + xi * xi + 1);
}
inline double ds_max_theta(double xi, double alpha) { return std::acos(-ds_w2(xi, alpha)); }

// EUCM (Khomutenko et al. 2016): z > -w rho, rho = sqrt(beta r^2 + z^2); on the unit
// sphere that is tan(pi - theta) = sqrt((1 - w^2) / (w^2 beta)).
inline double eucm_w(double alpha) { return alpha <= 0.5 ? alpha / (1 - alpha) : (1 - alpha) / alpha; }
inline double eucm_max_theta(double alpha, double beta) {
  const double w = eucm_w(alpha);
  return M_PI - std::atan(std::sqrt((1 - w * w) / (w * w * beta)));
}

inline RadtanDistortion radtan(double k1, double k2, double p1, double p2, double k3 = 0) {
  RadtanDistortion d;
  d.k1 = k1, d.k2 = k2, d.p1 = p1, d.p2 = p2, d.k3 = k3;
  return d;
}

struct CameraCase {
  std::string name;
  CameraModel model;
  double max_theta;  // radians from the optical axis: the model's own limit
  int width, height;
};
// gtest names a failing parameter by this rather than by its bytes.
inline void PrintTo(const CameraCase& c, std::ostream* os) { *os << c.name; }

inline std::vector<CameraCase> camera_cases() {
  // EuRoC MAV cam0 (kalibr pinhole-radtan): k2 > 0, so it never folds back.
  const auto euroc = radtan(-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05);
  // A wide-angle plumb_bob with k3 whose polynomial folds at ~60 deg.
  const auto plumb_bob = radtan(-0.3, 0.12, 0.001, -0.0005, -0.02);
  const auto k1_only = radtan(-0.3, 0, 0, 0);
  const auto omni_k5 = radtan(-0.28, 0.07, 0.0007, -0.0004, -0.005);
  const auto omni_k4 = radtan(-0.05, 0.01, 0.0008, 0.0003);
  return {
      {"pinhole_none", PinholeRadtan(458.654, 457.296, 367.215, 248.375), M_PI_2, 752, 480},
      {"pinhole_radtan4_euroc", PinholeRadtan(458.654, 457.296, 367.215, 248.375, euroc),
       std::atan(radtan_fold_radius(euroc)), 752, 480},
      {"pinhole_radtan5_k3", PinholeRadtan(500, 500, 320, 240, plumb_bob), std::atan(radtan_fold_radius(plumb_bob)),
       640, 480},
      {"pinhole_radtan_k1_only", PinholeRadtan(400, 400, 320, 240, k1_only), std::atan(radtan_fold_radius(k1_only)),
       640, 480},
      // The Insta360 Air-like 210 deg lens of config/examples/dual_fisheye.
      {"equidistant_210", Equidistant(258, 258, 511.5, 511.5, 0.02, -0.004, 0.0005, -0.0001),
       kb_max_theta(0.02, -0.004, 0.0005, -0.0001), 1024, 1024},
      // TUM VI cam0: monotonic all the way to pi.
      {"equidistant_tumvi",
       Equidistant(190.97847715128717, 190.9733070521226, 254.93170605935475, 256.8974428996504, 0.0034823894022493434,
                   0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182),
       kb_max_theta(0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182), 512,
       512},
      {"equidistant_turning", Equidistant(300, 300, 320, 240, -0.1, 0, 0, 0), kb_max_theta(-0.1, 0, 0, 0), 640, 480},
      {"fov", Fov(380, 381, 320, 240, 0.92), M_PI_2, 640, 480},
      {"omni_none_xi_0.9", OmniRadtan(0.9, 700, 701, 320, 240), omni_max_theta(0.9, {}), 640, 480},
      {"omni_none_xi_1.5", OmniRadtan(1.5, 900, 901, 320, 240), omni_max_theta(1.5, {}), 640, 480},
      {"omni_radtan5", OmniRadtan(0.9, 700, 701, 320, 240, omni_k5), omni_max_theta(0.9, omni_k5), 640, 480},
      {"omni_radtan4_xi_1.2", OmniRadtan(1.2, 800, 800, 320, 240, omni_k4), omni_max_theta(1.2, omni_k4), 640, 480},
      {"ds_tumvi", DoubleSphere(-0.17, 0.59, 156.6, 156.5, 254.9, 256.9), ds_max_theta(-0.17, 0.59), 512, 512},
      {"ds_alpha_below_half", DoubleSphere(0.7, 0.3, 350, 351, 320, 240), ds_max_theta(0.7, 0.3), 640, 480},
      {"eucm", Eucm(0.6, 1.1, 350, 351, 320, 240), eucm_max_theta(0.6, 1.1), 640, 480},
      {"eucm_alpha_below_half", Eucm(0.3, 0.8, 350, 351, 320, 240), eucm_max_theta(0.3, 0.8), 640, 480},
  };
}

}  // namespace omniview::testing
