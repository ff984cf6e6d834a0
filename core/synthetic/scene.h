// Synthetic scenes for tests, demos and the mock robot: analytic surfaces with a smooth,
// direction-dependent procedural texture, ray-cast through calibrated camera models.
//
// Golden-image tests build a scene whose geometry coincides with a view's projection
// surface (a wall for a perspective view, the floor for a bird's-eye view, a cylinder or
// sphere for panoramas; see Scene::matching): the view rendered from the cameras must then
// equal the texture sampled at the view's surface points.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "core/geometry/pose.h"
#include "core/view/view_spec.h"

namespace omniview::synthetic {

inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();

struct Plane {      // points p with normal . p = offset, optionally clipped to the box [lo, hi]
  Vec3 normal = Vec3::UnitZ();
  double offset = 0;
  Vec3 lo = Vec3::Constant(-kUnbounded), hi = Vec3::Constant(kUnbounded);
};
struct Box {        // axis-aligned; seen from inside (a room) or outside (furniture)
  Vec3 lo = Vec3::Zero(), hi = Vec3::Ones();
};
struct Sphere {     // |p - centre| = radius, seen from inside or outside
  Vec3 centre = Vec3::Zero();
  double radius = 1;
};
struct Cylinder {   // vertical: |(p - centre).xy| = radius, z_min <= p.z <= z_max (no caps)
  Vec3 centre = Vec3::Zero();
  double radius = 1, z_min = 0, z_max = 1;
};
using Shape = std::variant<Plane, Box, Sphere, Cylinder>;

// How a surface looks. The default is the bare test texture(), which is what golden
// references sample; the rest dresses surfaces up for example images a person looks at.
struct Material {
  double texture_contrast = 1;           // 1: texture() as is; 0: plain `base`
  Vec3 base = Vec3(150, 160, 170);       // BGR the texture is blended toward
  double grid_m = 0;                     // soft dark lines every grid_m metres (0: none)
  double tiles_m = 0;                    // soft light/dark checker of this period (0: none)
  bool lit = false;                      // shade by orientation: walls, floor, ceiling differ
};

struct Hit {
  double t = 0;     // origin + t * dir
  Vec3 point;
  Vec3 normal;      // unit, facing the ray's origin
  size_t shape = 0; // index in the order of Scene::add
};

class Scene {
 public:
  // Any one shape (Plane, Box, ...) or a Shape. Built in place: copying a variant that
  // holds another alternative trips GCC's -Wmaybe-uninitialized under ASan.
  template <typename S>
  Scene& add(const S& shape, const Material& material = {}) {
    if constexpr (std::is_same_v<S, Shape>) {
      shapes_.push_back(shape);
    } else {
      shapes_.emplace_back(std::in_place_type<S>, shape);
    }
    materials_.push_back(material);
    return *this;
  }
  size_t size() const { return shapes_.size(); }

  // Nearest hit along origin + t * dir with t > 1e-9 (dir need not be unit).
  std::optional<Hit> intersect(const Vec3& origin, const Vec3& dir) const;
  bool intersect(const Vec3& origin, const Vec3& dir, double& t, Vec3& point) const;

  // BGR in [0, 255] that a camera sees at a hit: the hit shape's material applied to texture().
  Vec3 colour(const Hit& hit) const;

  // BGR colour in [0, 255] at a world point: sums of a few sinusoids per channel, each
  // running along a different 3D direction, so any mirrored axis, wrong rotation or
  // shift of a few pixels changes the picture; band-limited so resampling keeps it.
  static Vec3 texture(const Vec3& p);

  // Single-surface scenes with the bare texture, in world coordinates.
  static Scene plane(const Vec3& normal, double offset);  // e.g. a wall x = d: ({1,0,0}, d)
  static Scene floor(double z = 0) { return plane(Vec3::UnitZ(), z); }
  static Scene cylinder(double radius, const Vec3& axis_point = Vec3::Zero());  // vertical, tall
  static Scene sphere(double radius, const Vec3& centre = Vec3::Zero());

  // The scene that coincides with `view`'s projection surface, the view's frame placed at
  // T_world_frame: the plane at `distance` (perspective), the ground z = ground_z of the
  // view's frame (bird's-eye), the central cylinder (cylindrical), the sphere (others).
  // Throws std::invalid_argument for a cylindrical view whose axis is not vertical in the
  // world (the synthetic cylinder is vertical).
  static Scene matching(const ViewSpec& view, const Pose& T_world_frame = Pose::Identity());

  // The bundled example's room (8 x 5.5 x 3 m, floor at z = 0): distinct walls, tiled floor,
  // panelled ceiling, two columns and two cabinets, so parallax shows in every view.
  static Scene room();

 private:
  std::vector<Shape> shapes_;
  std::vector<Material> materials_;
};

}  // namespace omniview::synthetic
