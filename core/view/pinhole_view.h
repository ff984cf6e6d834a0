// Perspective and bird's-eye views: a virtual pinhole camera.
//
// Square pixels, principal point ((W-1)/2, (H-1)/2), hfov spanning the outer pixel edges:
// f = (W/2) / tan(hfov/2). The perspective surface is the plane `distance` ahead of the
// camera (x = distance in the view frame); the bird's-eye surface is the ground plane
// z = ground_z of the view's parent frame, with the camera `height` above it.
#pragma once

#include "core/view/view.h"

namespace omniview {

class PinholeView : public View {
 public:
  explicit PinholeView(const ViewSpec& spec);

  double focal() const { return f_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }

  bool pixel_to_direction(double u, double v, Vec3& dir) const override;
  bool point_to_pixel(const Vec3& point, Vec2& uv) const override;

 protected:
  void surface_row_points(int v, float* x, float* y, float* z, uint8_t* valid) const override;
  void surface_points_at(int v, const int* columns, int n, float* x, float* y, float* z,
                         uint8_t* valid) const override;
  double surface_range(const Vec3& unit_dir) const override;

 private:
  template <typename Column>
  void points(int v, Column column, int n, float* x, float* y, float* z, uint8_t* valid) const;

  double f_, cx_, cy_;
  Vec3 down_in_view_;  // the parent frame's -z expressed in the view frame (bird's-eye)
};

}  // namespace omniview
