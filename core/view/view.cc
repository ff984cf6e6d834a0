#include "core/view/view.h"

#include <algorithm>

#include "core/view/fisheye_view.h"
#include "core/view/panorama_view.h"
#include "core/view/pinhole_view.h"

namespace omniview {

std::unique_ptr<View> View::create(const ViewSpec& spec) {
  validate(spec);
  switch (spec.type) {
    case ViewType::kPerspective:
    case ViewType::kBirdseye:
      return std::make_unique<PinholeView>(spec);
    case ViewType::kCylindrical:
    case ViewType::kMercator:
    case ViewType::kEquirectangular:
      return std::make_unique<PanoramaView>(spec);
    case ViewType::kFisheye:
      return std::make_unique<FisheyeView>(spec);
  }
  throw std::invalid_argument("view '" + spec.name + "': unhandled type");
}

View::View(const ViewSpec& spec) : spec_(spec) {
  const Pose T = spec.T_frame_view();
  down_ = T.linear().transpose() * Vec3(0, 0, -1);
  height_ = T.translation().z() - spec.ground_z;
}

bool View::pixel_to_point(double u, double v, Vec3& point) const {
  Vec3 dir;
  if (!pixel_to_direction(u, v, dir)) return false;
  const Vec3 unit = dir.normalized();
  double range = surface_range(unit);
  if (!(range > 0)) return false;
  if (spec_.ground) {
    const double descent = unit.dot(down_);  // metres down per metre along the ray
    if (descent > 0) range = std::min(range, height_ / descent);
  }
  point = range * unit;
  return true;
}

void View::row_points(int v, float* x, float* y, float* z, uint8_t* valid) const {
  surface_row_points(v, x, y, z, valid);
  if (!spec_.ground) return;
  for (int u = 0; u < width(); ++u) cut_at_ground(x[u], y[u], z[u]);
}

void View::surface_row_points(int v, float* x, float* y, float* z, uint8_t* valid) const {
  for (int u = 0; u < width(); ++u) {
    Vec3 dir = Vec3::Zero();
    double range = 0;
    valid[u] = pixel_to_direction(u, v, dir) && (range = surface_range(dir.normalized())) > 0;
    const Vec3 p = valid[u] ? Vec3(range * dir.normalized()) : Vec3::Zero();
    x[u] = static_cast<float>(p.x());
    y[u] = static_cast<float>(p.y());
    z[u] = static_cast<float>(p.z());
  }
}

void View::cut_at_ground(float& x, float& y, float& z) const {
  // The point is `descent` metres below the origin; the ground is height_ below it.
  const float descent = x * static_cast<float>(down_.x()) + y * static_cast<float>(down_.y()) +
                        z * static_cast<float>(down_.z());
  const float h = static_cast<float>(height_);
  if (descent <= h) return;
  const float scale = h / descent;
  x *= scale, y *= scale, z *= scale;
}

void View::points_at(int v, const int* columns, int n, float* x, float* y, float* z, uint8_t* valid) const {
  surface_points_at(v, columns, n, x, y, z, valid);
  if (!spec_.ground) return;
  for (int i = 0; i < n; ++i) cut_at_ground(x[i], y[i], z[i]);
}

void View::surface_points_at(int v, const int* columns, int n, float* x, float* y, float* z, uint8_t* valid) const {
  for (int i = 0; i < n; ++i) {
    Vec3 dir = Vec3::Zero();
    double range = 0;
    valid[i] = pixel_to_direction(columns[i], v, dir) && (range = surface_range(dir.normalized())) > 0;
    const Vec3 p = valid[i] ? Vec3(range * dir.normalized()) : Vec3::Zero();
    x[i] = static_cast<float>(p.x());
    y[i] = static_cast<float>(p.y());
    z[i] = static_cast<float>(p.z());
  }
}

}  // namespace omniview
