#include "core/view/panorama_view.h"

#include <cmath>

namespace omniview {
namespace {
constexpr double kRadiansPerDegree = M_PI / 180;
double mercator_y(double phi) { return std::log(std::tan(M_PI / 4 + phi / 2)); }
}  // namespace

PanoramaView::PanoramaView(const ViewSpec& spec) : View(spec) {
  span_ = spec.azimuth_span_deg * kRadiansPerDegree;
  switch (spec.type) {
    case ViewType::kCylindrical:
      top_ = std::tan(spec.vfov_deg * kRadiansPerDegree / 2);
      bottom_ = -top_;
      break;
    case ViewType::kMercator:
      top_ = mercator_y(spec.lat_max_deg * kRadiansPerDegree);
      bottom_ = mercator_y(spec.lat_min_deg * kRadiansPerDegree);
      break;
    default:
      top_ = spec.lat_max_deg * kRadiansPerDegree;
      bottom_ = spec.lat_min_deg * kRadiansPerDegree;
  }
  cos_az_.resize(spec.width);
  sin_az_.resize(spec.width);
  for (int u = 0; u < spec.width; ++u) {
    cos_az_[u] = static_cast<float>(std::cos(azimuth(u)));
    sin_az_[u] = static_cast<float>(std::sin(azimuth(u)));
  }
}

double PanoramaView::azimuth(double u) const { return span_ * (0.5 - (u + 0.5) / width()); }

double PanoramaView::row_coordinate(double v) const {
  return top_ - (top_ - bottom_) * (v + 0.5) / height();
}

bool PanoramaView::pixel_to_direction(double u, double v, Vec3& dir) const {
  const double lambda = azimuth(u), c = row_coordinate(v);
  if (spec_.type == ViewType::kCylindrical) {
    dir = Vec3(std::cos(lambda), std::sin(lambda), c);
    return true;
  }
  const double phi = spec_.type == ViewType::kMercator ? std::atan(std::sinh(c)) : c;
  dir = Vec3(std::cos(phi) * std::cos(lambda), std::cos(phi) * std::sin(lambda), std::sin(phi));
  return true;
}

bool PanoramaView::point_to_pixel(const Vec3& p, Vec2& uv) const {
  const double horizontal = std::hypot(p.x(), p.y());
  if (!(p.norm() > 1e-12)) return false;
  const double lambda = std::atan2(p.y(), p.x());
  double c;
  if (spec_.type == ViewType::kCylindrical) {
    if (horizontal < 1e-12) return false;
    c = p.z() / horizontal;
  } else {
    const double phi = std::atan2(p.z(), horizontal);
    c = spec_.type == ViewType::kMercator ? mercator_y(phi) : phi;
  }
  uv = Vec2((0.5 - lambda / span_) * width() - 0.5, (top_ - c) / (top_ - bottom_) * height() - 0.5);
  return std::isfinite(uv.y()) && in_image(uv);
}

double PanoramaView::surface_range(const Vec3& d) const {
  if (spec_.type == ViewType::kCylindrical) {
    const double horizontal = std::hypot(d.x(), d.y());
    return horizontal > 1e-12 ? spec_.radius / horizontal : -1;
  }
  return spec_.radius;
}

// Surface points of pixels (column(i), v), i < n: one body for row_points and points_at.
template <typename Column>
void PanoramaView::points(int v, Column column, int n, float* x, float* y, float* z, uint8_t* valid) const {
  const double c = row_coordinate(v);
  const float r = static_cast<float>(spec_.radius);
  float horizontal, vertical;
  if (spec_.type == ViewType::kCylindrical) {
    horizontal = r;
    vertical = static_cast<float>(spec_.radius * c);
  } else {
    const double phi = spec_.type == ViewType::kMercator ? std::atan(std::sinh(c)) : c;
    horizontal = static_cast<float>(spec_.radius * std::cos(phi));
    vertical = static_cast<float>(spec_.radius * std::sin(phi));
  }
  const float* __restrict cos_az = cos_az_.data();
  const float* __restrict sin_az = sin_az_.data();
  for (int i = 0; i < n; ++i) {
    const int u = column(i);
    x[i] = horizontal * cos_az[u];
    y[i] = horizontal * sin_az[u];
    z[i] = vertical;
    valid[i] = 1;
  }
}

void PanoramaView::surface_row_points(int v, float* x, float* y, float* z, uint8_t* valid) const {
  points(v, [](int i) { return i; }, width(), x, y, z, valid);
}

void PanoramaView::surface_points_at(int v, const int* columns, int n, float* x, float* y, float* z, uint8_t* valid) const {
  points(v, [columns](int i) { return columns[i]; }, n, x, y, z, valid);
}

}  // namespace omniview
