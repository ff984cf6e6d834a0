#include "core/synthetic/scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>

namespace omniview::synthetic {
namespace {

constexpr double kEps = 1e-9;

bool inside(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (p.array() >= lo.array() - kEps).all() && (p.array() <= hi.array() + kEps).all();
}

std::optional<double> hit(const Plane& s, const Vec3& o, const Vec3& d) {
  const double denom = s.normal.dot(d);
  if (std::abs(denom) < 1e-15) return std::nullopt;
  const double t = (s.offset - s.normal.dot(o)) / denom;
  if (!(t > kEps) || !inside(o + t * d, s.lo, s.hi)) return std::nullopt;
  return t;
}

// Slab test: entering the box from outside, or leaving it from inside.
std::optional<double> hit(const Box& b, const Vec3& o, const Vec3& d) {
  double t_in = -kUnbounded, t_out = kUnbounded;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < 1e-15) {
      if (o[i] < b.lo[i] || o[i] > b.hi[i]) return std::nullopt;  // parallel to and outside this slab
      continue;
    }
    double t0 = (b.lo[i] - o[i]) / d[i], t1 = (b.hi[i] - o[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    t_in = std::max(t_in, t0);
    t_out = std::min(t_out, t1);
  }
  if (t_in > t_out) return std::nullopt;
  if (t_in > kEps) return t_in;
  if (t_out > kEps) return t_out;
  return std::nullopt;
}

// Smallest root t > eps of a t^2 + 2 b t + c = 0 that `accept` takes.
template <typename Accept>
std::optional<double> nearest_root(double a, double b, double c, Accept accept) {
  if (a < 1e-15) return std::nullopt;
  const double disc = b * b - a * c;
  if (disc < 0) return std::nullopt;
  const double root = std::sqrt(disc);
  for (double t : {(-b - root) / a, (-b + root) / a}) {
    if (t > kEps && accept(t)) return t;
  }
  return std::nullopt;
}

std::optional<double> hit(const Sphere& s, const Vec3& o, const Vec3& d) {
  const Vec3 oc = o - s.centre;
  return nearest_root(d.squaredNorm(), oc.dot(d), oc.squaredNorm() - s.radius * s.radius, [](double) { return true; });
}

std::optional<double> hit(const Cylinder& s, const Vec3& o, const Vec3& d) {
  const Vec3 oc = o - s.centre;
  return nearest_root(d.x() * d.x() + d.y() * d.y(), oc.x() * d.x() + oc.y() * d.y(),
                      oc.x() * oc.x() + oc.y() * oc.y() - s.radius * s.radius, [&](double t) {
                        const double z = o.z() + t * d.z();
                        return z >= s.z_min && z <= s.z_max;
                      });
}

Vec3 normal_at(const Shape& shape, const Vec3& p) {
  return std::visit(
      [&](const auto& s) -> Vec3 {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Plane>) {
          return s.normal.normalized();
        } else if constexpr (std::is_same_v<S, Box>) {
          // The face the point lies on: the axis along which it is closest to lo or hi.
          const Vec3 to_face = (p - s.lo).cwiseAbs().cwiseMin((p - s.hi).cwiseAbs());
          int axis = 0;
          to_face.minCoeff(&axis);
          return Vec3::Unit(axis);
        } else if constexpr (std::is_same_v<S, Sphere>) {
          return (p - s.centre).normalized();
        } else {
          return Vec3(p.x() - s.centre.x(), p.y() - s.centre.y(), 0).normalized();
        }
      },
      shape);
}

}  // namespace

std::optional<Hit> Scene::intersect(const Vec3& origin, const Vec3& dir) const {
  std::optional<double> best;
  size_t best_index = 0;
  for (size_t i = 0; i < shapes_.size(); ++i) {
    const auto t = std::visit([&](const auto& s) { return hit(s, origin, dir); }, shapes_[i]);
    if (t && (!best || *t < *best)) best = t, best_index = i;
  }
  if (!best) return std::nullopt;
  Hit h;
  h.t = *best;
  h.point = origin + *best * dir;
  h.shape = best_index;
  h.normal = normal_at(shapes_[best_index], h.point);
  if (h.normal.dot(dir) > 0) h.normal = -h.normal;
  return h;
}

bool Scene::intersect(const Vec3& origin, const Vec3& dir, double& t, Vec3& point) const {
  const auto h = intersect(origin, dir);
  if (!h) return false;
  t = h->t;
  point = h->point;
  return true;
}

Scene Scene::plane(const Vec3& normal, double offset) {
  Scene s;
  s.add(Plane{normal, offset});
  return s;
}

Scene Scene::cylinder(double radius, const Vec3& axis_point) {
  Scene s;
  s.add(Cylinder{axis_point, radius, -1e6, 1e6});  // tall enough for any view's rows
  return s;
}

Scene Scene::sphere(double radius, const Vec3& centre) {
  Scene s;
  s.add(Sphere{centre, radius});
  return s;
}

Scene Scene::matching(const ViewSpec& view, const Pose& T_world_frame) {
  const Pose T_world_view = T_world_frame * view.T_frame_view();
  switch (view.type) {
    case ViewType::kPerspective: {
      const Vec3 n = T_world_view.linear().col(0);  // the plane x = distance of the view frame
      return plane(n, n.dot(T_world_view.translation()) + view.distance);
    }
    case ViewType::kBirdseye: {
      const Vec3 n = T_world_frame.linear().col(2);  // the plane z = ground_z of the view's frame
      return plane(n, n.dot(T_world_frame.translation()) + view.ground_z);
    }
    case ViewType::kCylindrical:
      if (std::abs(T_world_view.linear().col(2).z()) < 1 - 1e-9) {
        throw std::invalid_argument("Scene::matching: cylindrical view '" + view.name +
                                    "' is tilted; synthetic cylinders are vertical");
      }
      return cylinder(view.radius, T_world_view.translation());
    default:
      return sphere(view.radius, T_world_view.translation());
  }
}

}  // namespace omniview::synthetic
