// Pinhole projection with optional radial-tangential distortion
// (kalibr: camera_model pinhole, distortion_model radtan | none).
//   m = (x/z, y/z),  d = radtan(m),  u = fu*dx + pu,  v = fv*dy + pv
// Imageable: z > 0 and |m| within the monotonic range of the distortion.
#pragma once

#include <Eigen/Core>

#include "core/camera/radtan_distortion.h"

namespace omniview {

class PinholeRadtan {
 public:
  PinholeRadtan(double fu, double fv, double pu, double pv, const RadtanDistortion& d = {});

  template <typename S>
  inline bool project(S x, S y, S z, S& u, S& v) const {
    const S safe_z = z > S(1e-9) ? z : S(1);
    const S mx = x / safe_z, my = y / safe_z;
    S dx, dy;
    dist_.distort(mx, my, dx, dy);  // identity for zero coefficients; no branch keeps SIMD
    u = S(fu_) * dx + S(pu_);
    v = S(fv_) * dy + S(pv_);
    return (z > S(1e-9)) & (mx * mx + my * my <= S(max_r2_));
  }
  bool unproject(double u, double v, Eigen::Vector3d& ray) const;

  double fu() const { return fu_; }
  double fv() const { return fv_; }
  double pu() const { return pu_; }
  double pv() const { return pv_; }
  const RadtanDistortion& distortion() const { return dist_; }

 private:
  double fu_, fv_, pu_, pv_;
  RadtanDistortion dist_;
  double max_r2_;
};

}  // namespace omniview
