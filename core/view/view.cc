#include "core/view/view.h"

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

bool View::pixel_to_point(double u, double v, Vec3& point) const {
  Vec3 dir;
  if (!pixel_to_direction(u, v, dir)) return false;
  const Vec3 unit = dir.normalized();
  const double range = surface_range(unit);
  if (!(range > 0)) return false;
  point = range * unit;
  return true;
}

void View::row_points(int v, float* x, float* y, float* z, uint8_t* valid) const {
  for (int u = 0; u < width(); ++u) {
    Vec3 p = Vec3::Zero();
    valid[u] = pixel_to_point(u, v, p);
    x[u] = static_cast<float>(p.x());
    y[u] = static_cast<float>(p.y());
    z[u] = static_cast<float>(p.z());
  }
}

void View::points_at(int v, const int* columns, int n, float* x, float* y, float* z, uint8_t* valid) const {
  for (int i = 0; i < n; ++i) {
    Vec3 p = Vec3::Zero();
    valid[i] = pixel_to_point(columns[i], v, p);
    x[i] = static_cast<float>(p.x());
    y[i] = static_cast<float>(p.y());
    z[i] = static_cast<float>(p.z());
  }
}

}  // namespace omniview
