// Double sphere model of Usenko, Demmel & Cremers (3DV 2018)
// (kalibr: camera_model ds [xi alpha fu fv pu pv], distortion none).
//   d1 = |p|,  zz = xi d1 + z,  d2 = |(x, y, zz)|,  den = alpha d2 + (1 - alpha) zz
//   u = fu x / den + pu,  v = fv y / den + pv
// Imageable: z > -w2 d1 (paper eq. 43-45).
#pragma once

#include <Eigen/Core>

namespace omniview {

class DoubleSphere {
 public:
  DoubleSphere(double xi, double alpha, double fu, double fv, double pu, double pv);

  template <typename S>
  inline bool project(S x, S y, S z, S& u, S& v) const {
    const S xy2 = x * x + y * y;
    const S d1 = std::sqrt(xy2 + z * z);
    const S zz = S(xi_) * d1 + z;
    const S d2 = std::sqrt(xy2 + zz * zz);
    const S den = S(alpha_) * d2 + (S(1) - S(alpha_)) * zz;
    const S safe_den = den > S(1e-12) ? den : S(1);
    u = S(fu_) * x / safe_den + S(pu_);
    v = S(fv_) * y / safe_den + S(pv_);
    return (z > -S(w2_) * d1) & (den > S(1e-12));
  }
  bool unproject(double u, double v, Eigen::Vector3d& ray) const;

  double xi() const { return xi_; }
  double alpha() const { return alpha_; }
  double fu() const { return fu_; }
  double fv() const { return fv_; }
  double pu() const { return pu_; }
  double pv() const { return pv_; }

 private:
  double xi_, alpha_, fu_, fv_, pu_, pv_, w2_;
};

}  // namespace omniview
