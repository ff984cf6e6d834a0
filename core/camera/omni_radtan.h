// Unified (Mei) omnidirectional model with optional radial-tangential distortion
// (kalibr: camera_model omni [xi fu fv pu pv], distortion_model radtan | none).
//   m = (x, y) / (z + xi |p|),  d = radtan(m),  u = fu dx + pu,  v = fv dy + pv
// Imageable: z > -w |p| with w = xi for xi <= 1 and 1/xi beyond (points behind the
// projection sphere's horizon fold over), and |m| within the distortion's monotonic range.
#pragma once

#include <Eigen/Core>

#include "core/camera/radtan_distortion.h"

namespace omniview {

class OmniRadtan {
 public:
  OmniRadtan(double xi, double fu, double fv, double pu, double pv, const RadtanDistortion& d = {});

  template <typename S>
  inline bool project(S x, S y, S z, S& u, S& v) const {
    const S norm = std::sqrt(x * x + y * y + z * z);
    const S den = z + S(xi_) * norm;
    const S safe_den = den > S(1e-9) ? den : S(1);
    const S mx = x / safe_den, my = y / safe_den;
    S dx, dy;
    dist_.distort(mx, my, dx, dy);  // identity for zero coefficients; no branch keeps SIMD
    u = S(fu_) * dx + S(pu_);
    v = S(fv_) * dy + S(pv_);
    return (den > S(1e-9)) & (z > -S(w_) * norm) & (mx * mx + my * my <= S(max_r2_));
  }
  bool unproject(double u, double v, Eigen::Vector3d& ray) const;

  double xi() const { return xi_; }
  double fu() const { return fu_; }
  double fv() const { return fv_; }
  double pu() const { return pu_; }
  double pv() const { return pv_; }
  const RadtanDistortion& distortion() const { return dist_; }

 private:
  double xi_, fu_, fv_, pu_, pv_;
  RadtanDistortion dist_;
  double w_, max_r2_;
};

}  // namespace omniview
