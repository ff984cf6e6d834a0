#include "core/view/pinhole_view.h"

#include <cmath>

namespace omniview {

PinholeView::PinholeView(const ViewSpec& spec) : View(spec) {
  f_ = (spec.width / 2.0) / std::tan(spec.hfov_deg * M_PI / 360.0);
  cx_ = (spec.width - 1) / 2.0;
  cy_ = (spec.height - 1) / 2.0;
  down_in_view_ = spec.T_frame_view().linear().transpose() * Vec3(0, 0, -1);
}

bool PinholeView::pixel_to_direction(double u, double v, Vec3& dir) const {
  // Optical ((u-cx)/f, (v-cy)/f, 1) in view axes: x = optical z, y = -optical x, z = -optical y.
  dir = Vec3(1.0, -(u - cx_) / f_, -(v - cy_) / f_);
  return spec_.type == ViewType::kPerspective || surface_range(dir.normalized()) > 0;
}

bool PinholeView::point_to_pixel(const Vec3& p, Vec2& uv) const {
  if (!(p.x() > 1e-12)) return false;
  uv = Vec2(cx_ - f_ * p.y() / p.x(), cy_ - f_ * p.z() / p.x());
  return in_image(uv);
}

double PinholeView::surface_range(const Vec3& d) const {
  if (spec_.type == ViewType::kPerspective) return d.x() > 0 ? spec_.distance / d.x() : -1;
  const double descent = d.dot(down_in_view_);  // metres down per metre along the ray
  return descent > 1e-9 ? spec_.height_m / descent : -1;
}

// Surface points of pixels (column(i), v), i < n: one body for row_points and points_at,
// so both give the same bits.
template <typename Column>
void PinholeView::points(int v, Column column, int n, float* x, float* y, float* z, uint8_t* valid) const {
  const float inv_f = static_cast<float>(1.0 / f_);
  const float dz = static_cast<float>(-(v - cy_) / f_);
  const float cx = static_cast<float>(cx_);
  if (spec_.type == ViewType::kPerspective) {
    const float d = static_cast<float>(spec_.distance);
    for (int i = 0; i < n; ++i) {
      x[i] = d;
      y[i] = -(static_cast<float>(column(i)) - cx) * inv_f * d;
      z[i] = dz * d;
      valid[i] = 1;
    }
    return;
  }
  const float hx = static_cast<float>(down_in_view_.x()), hy = static_cast<float>(down_in_view_.y()),
              hz = static_cast<float>(down_in_view_.z());
  const float h = static_cast<float>(spec_.height_m);
  for (int i = 0; i < n; ++i) {
    const float dy = -(static_cast<float>(column(i)) - cx) * inv_f;
    const float descent = hx + dy * hy + dz * hz;  // dir = (1, dy, dz), not unit
    const bool hit = descent > 1e-6f;
    const float t = h / (hit ? descent : 1.0f);
    x[i] = t;
    y[i] = t * dy;
    z[i] = t * dz;
    valid[i] = hit;
  }
}

void PinholeView::surface_row_points(int v, float* x, float* y, float* z, uint8_t* valid) const {
  points(v, [](int i) { return i; }, width(), x, y, z, valid);
}

void PinholeView::surface_points_at(int v, const int* columns, int n, float* x, float* y, float* z, uint8_t* valid) const {
  points(v, [columns](int i) { return columns[i]; }, n, x, y, z, valid);
}

}  // namespace omniview
