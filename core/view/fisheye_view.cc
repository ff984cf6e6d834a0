#include "core/view/fisheye_view.h"

#include <algorithm>
#include <cmath>

#include "core/camera/fast_math.h"

namespace omniview {

FisheyeView::FisheyeView(const ViewSpec& spec) : View(spec) {
  half_fov_ = spec.fov_deg * M_PI / 360;
  f_ = (std::min(spec.width, spec.height) / 2.0) / half_fov_;
  cx_ = (spec.width - 1) / 2.0;
  cy_ = (spec.height - 1) / 2.0;
}

bool FisheyeView::pixel_to_direction(double u, double v, Vec3& dir) const {
  // Optical offsets (right, down) -> view axes (left = -right, up = -down).
  const double ox = (u - cx_) / f_, oy = (v - cy_) / f_;
  const double theta = std::hypot(ox, oy);
  if (theta > half_fov_ || theta > M_PI) return false;
  const double s = theta > 1e-12 ? std::sin(theta) / theta : 1.0;
  dir = Vec3(std::cos(theta), -ox * s, -oy * s);
  return true;
}

bool FisheyeView::point_to_pixel(const Vec3& p, Vec2& uv) const {
  const double lateral = std::hypot(p.y(), p.z());
  if (!(p.norm() > 1e-12)) return false;
  const double theta = std::atan2(lateral, p.x());
  if (theta > half_fov_) return false;
  const double scale = lateral > 1e-12 ? f_ * theta / lateral : 0.0;
  uv = Vec2(cx_ - p.y() * scale, cy_ - p.z() * scale);
  return in_image(uv);
}

// Surface points of pixels (column(i), v), i < n: one body for row_points and points_at.
template <typename Column>
void FisheyeView::points(int v, Column column, int n, float* x, float* y, float* z, uint8_t* valid) const {
  const float inv_f = static_cast<float>(1 / f_), cx = static_cast<float>(cx_);
  const float oy = static_cast<float>((v - cy_) / f_);
  const float max_theta2 = static_cast<float>(std::min(half_fov_, M_PI) * std::min(half_fov_, M_PI));
  const float r = static_cast<float>(spec_.radius);
  for (int i = 0; i < n; ++i) {
    const float ox = (static_cast<float>(column(i)) - cx) * inv_f;
    const float theta2 = ox * ox + oy * oy;
    float cos_theta, sinc_theta;
    fast::cos_and_sinc(theta2, cos_theta, sinc_theta);
    x[i] = r * cos_theta;
    y[i] = -r * ox * sinc_theta;
    z[i] = -r * oy * sinc_theta;
    valid[i] = theta2 <= max_theta2;
  }
}

void FisheyeView::surface_row_points(int v, float* x, float* y, float* z, uint8_t* valid) const {
  points(v, [](int i) { return i; }, width(), x, y, z, valid);
}

void FisheyeView::surface_points_at(int v, const int* columns, int n, float* x, float* y, float* z, uint8_t* valid) const {
  points(v, [columns](int i) { return columns[i]; }, n, x, y, z, valid);
}

}  // namespace omniview
