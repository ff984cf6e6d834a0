// An ideal equidistant fisheye (the paper's "spherical" view) on a sphere of `radius`.
//
// Optical axis along the view's +x; angle from the axis theta = rho / f, with rho the
// distance from the principal point ((W-1)/2, (H-1)/2) and f chosen so that `fov`
// spans the shorter image side edge to edge: f = (min(W, H) / 2) / (fov / 2).
#pragma once

#include "core/view/view.h"

namespace omniview {

class FisheyeView : public View {
 public:
  explicit FisheyeView(const ViewSpec& spec);

  double focal() const { return f_; }

  bool pixel_to_direction(double u, double v, Vec3& dir) const override;
  bool point_to_pixel(const Vec3& point, Vec2& uv) const override;

 protected:
  void surface_row_points(int v, float* x, float* y, float* z, uint8_t* valid) const override;
  void surface_points_at(int v, const int* columns, int n, float* x, float* y, float* z,
                         uint8_t* valid) const override;
  double surface_range(const Vec3&) const override { return spec_.radius; }

 private:
  template <typename Column>
  void points(int v, Column column, int n, float* x, float* y, float* z, uint8_t* valid) const;

  double f_, cx_, cy_, half_fov_;
};

}  // namespace omniview
