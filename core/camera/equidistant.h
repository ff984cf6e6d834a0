// Kannala-Brandt fisheye with four coefficients (kalibr: pinhole + equidistant;
// OpenCV's cv::fisheye; Spot's KannalaBrandtModel).
//   theta = atan2(|(x, y)|, z)      -- not atan(r/z): lenses beyond 180 deg must work
//   d(theta) = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)
//   u = fu d (x/r) + pu,  v = fv d (y/r) + pv
// Imageable: theta up to where d(theta) stops increasing (at most pi, but not the point
// straight behind: at theta = pi the image direction is undefined).
#pragma once

#include <Eigen/Core>

#include "core/camera/fast_math.h"

namespace omniview {

class Equidistant {
 public:
  Equidistant(double fu, double fv, double pu, double pv, double k1, double k2, double k3,
              double k4);

  template <typename S>
  inline bool project(S x, S y, S z, S& u, S& v) const {
    const S r2 = x * x + y * y;
    const S r = std::sqrt(r2);
    const S theta = fast::atan2_radius(r, z);
    const S t2 = theta * theta;
    const S d = theta * (S(1) + t2 * (S(k1_) + t2 * (S(k2_) + t2 * (S(k3_) + t2 * S(k4_)))));
    // Near the axis d/r -> 1/z; avoid 0/0 exactly on it.
    const S scale = r > S(1e-12) ? d / r : S(1) / (z > S(0) ? z : S(1));
    u = S(fu_) * x * scale + S(pu_);
    v = S(fv_) * y * scale + S(pv_);
    // On the axis behind the lens (theta = pi) the direction x/r is undefined: the point
    // images onto the whole rim circle, not the principal point, so it is not imageable.
    return (theta <= S(max_theta_)) & ((r > S(1e-12)) | (z > S(0)));
  }
  bool unproject(double u, double v, Eigen::Vector3d& ray) const;

  double max_theta() const { return max_theta_; }
  double fu() const { return fu_; }
  double fv() const { return fv_; }
  double pu() const { return pu_; }
  double pv() const { return pv_; }
  Eigen::Vector4d k() const { return {k1_, k2_, k3_, k4_}; }

 private:
  double distorted_angle(double theta) const;
  double fu_, fv_, pu_, pv_, k1_, k2_, k3_, k4_;
  double max_theta_;
};

}  // namespace omniview
