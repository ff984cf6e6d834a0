#include "core/view/fisheye_view.h"

#include <algorithm>
#include <cmath>

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

}  // namespace omniview
