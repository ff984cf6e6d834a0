// Field-of-view model of Devernay & Faugeras (kalibr: pinhole + fov, one parameter w).
//   m = (x/z, y/z), r = |m|,  r_d = atan(2 r tan(w/2)) / w,  u = fu r_d m_x / r + pu
// Imageable: z > 0.
#pragma once

#include <Eigen/Core>

#include "core/camera/fast_math.h"

namespace omniview {

class Fov {
 public:
  Fov(double fu, double fv, double pu, double pv, double w);

  template <typename S>
  inline bool project(S x, S y, S z, S& u, S& v) const {
    const S safe_z = z > S(1e-9) ? z : S(1);
    const S mx = x / safe_z, my = y / safe_z;
    const S r = std::sqrt(mx * mx + my * my);
    const S rd = fast::atan_nonneg(r * S(two_tan_half_w_)) / S(w_);
    const S scale = r > S(1e-9) ? rd / r : S(two_tan_half_w_ / w_);
    u = S(fu_) * mx * scale + S(pu_);
    v = S(fv_) * my * scale + S(pv_);
    return z > S(1e-9);
  }
  bool unproject(double u, double v, Eigen::Vector3d& ray) const;

  double fu() const { return fu_; }
  double fv() const { return fv_; }
  double pu() const { return pu_; }
  double pv() const { return pv_; }
  double w() const { return w_; }

 private:
  double fu_, fv_, pu_, pv_, w_, two_tan_half_w_;
};

}  // namespace omniview
