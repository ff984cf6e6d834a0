// Synthetic scenes for tests, demos and the mock robot: analytic surfaces with a smooth,
// direction-dependent procedural texture, ray-cast through calibrated camera models.
//
// Golden-image tests build a scene whose geometry coincides with a view's projection
// surface (a wall for a perspective view, the floor for a bird's-eye view, a cylinder or
// sphere for panoramas): the view rendered from the cameras must then equal the texture
// sampled at the view's surface points.
#pragma once

#include <optional>
#include <variant>
#include <vector>

#include "core/geometry/pose.h"

namespace omniview::synthetic {

struct Plane {      // points p with normal . p = offset
  Vec3 normal = Vec3::UnitZ();
  double offset = 0;
};
struct Sphere {     // |p - centre| = radius, seen from inside or outside
  Vec3 centre = Vec3::Zero();
  double radius = 1;
};
struct Cylinder {   // vertical: |(p - centre).xy| = radius, z_min <= p.z <= z_max
  Vec3 centre = Vec3::Zero();
  double radius = 1, z_min = 0, z_max = 1;
};
using Shape = std::variant<Plane, Sphere, Cylinder>;

struct Hit {
  Vec3 point;
  Vec3 normal;  // unit, facing the ray's origin
};

class Scene {
 public:
  Scene& add(const Shape& shape);

  // Nearest hit along origin + t * dir with t > 1e-9.
  std::optional<Hit> intersect(const Vec3& origin, const Vec3& dir) const;

  // What a camera sees at a hit: texture(), or for a decorated scene (the example room)
  // a calmer version of it with 1 m grid lines and shading by surface orientation, so a
  // person can tell the walls from the floor.
  Vec3 colour(const Hit& hit) const;
  Scene& decorated(bool on = true) {
    decorated_ = on;
    return *this;
  }

  // BGR colour in [0, 255] at a world point: sums of a few sinusoids per channel, each
  // running along a different 3D direction, so any mirrored axis, wrong rotation or
  // shift of a few pixels changes the picture.
  static Vec3 texture(const Vec3& p);

  // The bundled example's room: floor z = 0, ceiling, four walls, two columns; decorated.
  static Scene room();

 private:
  std::vector<Shape> shapes_;
  bool decorated_ = false;
};

}  // namespace omniview::synthetic
