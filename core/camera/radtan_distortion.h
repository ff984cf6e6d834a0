// Radial-tangential (Brown-Conrady, OpenCV's 5-coefficient plumb_bob) distortion of
// normalised image coordinates, shared by the pinhole and omni models.
//
// Coefficients k1 k2 p1 p2 [k3] as kalibr and OpenCV. The polynomial folds back on
// itself far from the centre, which would image points behind the fold at the wrong
// place; max_radius() is where radial distortion stops being monotonic and the models
// treat anything beyond it as not imageable.
#pragma once

#include <array>
#include <Eigen/Core>

namespace omniview {

struct RadtanDistortion {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;

  bool is_zero() const { return k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0; }

  template <typename S>
  inline void distort(S mx, S my, S& dx, S& dy) const {
    const S x2 = mx * mx, y2 = my * my, xy = mx * my, r2 = x2 + y2;
    const S radial = S(1) + r2 * (S(k1) + r2 * (S(k2) + r2 * S(k3)));
    dx = mx * radial + S(2 * p1) * xy + S(p2) * (r2 + S(2) * x2);
    dy = my * radial + S(p1) * (r2 + S(2) * y2) + S(2 * p2) * xy;
  }

  // Inverts distort() by Newton's method; false if it does not converge. Models pass their
  // cached max_radius() as `max_r`; the short form computes it.
  bool undistort(double dx, double dy, double& mx, double& my) const;
  bool undistort(double dx, double dy, double& mx, double& my, double max_r) const;

  // Largest normalised radius up to which r * radial(r) increases (capped at `cap`).
  double max_radius(double cap = 1e3) const;
};

}  // namespace omniview
