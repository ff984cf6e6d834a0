// Enhanced unified camera model of Khomutenko, Garcia & Martinet (RA-L 2016)
// (kalibr: camera_model eucm [alpha beta fu fv pu pv], distortion none).
//   rho = sqrt(beta (x^2 + y^2) + z^2),  den = alpha rho + (1 - alpha) z
//   u = fu x / den + pu,  v = fv y / den + pv
// Imageable: z > -w rho, w = alpha/(1-alpha) for alpha <= 0.5, else (1-alpha)/alpha.
#pragma once

#include <Eigen/Core>

namespace omniview {

class Eucm {
 public:
  Eucm(double alpha, double beta, double fu, double fv, double pu, double pv);

  template <typename S>
  inline bool project(S x, S y, S z, S& u, S& v) const {
    const S rho = std::sqrt(S(beta_) * (x * x + y * y) + z * z);
    const S den = S(alpha_) * rho + (S(1) - S(alpha_)) * z;
    const S safe_den = den > S(1e-12) ? den : S(1);
    u = S(fu_) * x / safe_den + S(pu_);
    v = S(fv_) * y / safe_den + S(pv_);
    return (z > -S(w_) * rho) & (den > S(1e-12));
  }
  bool unproject(double u, double v, Eigen::Vector3d& ray) const;

  double alpha() const { return alpha_; }
  double beta() const { return beta_; }
  double fu() const { return fu_; }
  double fv() const { return fv_; }
  double pu() const { return pu_; }
  double pv() const { return pv_; }

 private:
  double alpha_, beta_, fu_, fv_, pu_, pv_, w_;
};

}  // namespace omniview
