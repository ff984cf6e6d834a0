#include "core/synthetic/scene.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace omniview::synthetic {
namespace {

constexpr double kEps = 1e-9;

std::optional<double> hit(const Plane& s, const Vec3& o, const Vec3& d) {
  const double denom = s.normal.dot(d);
  if (std::abs(denom) < 1e-12) return std::nullopt;
  const double t = (s.offset - s.normal.dot(o)) / denom;
  return t > kEps ? std::optional(t) : std::nullopt;
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

}  // namespace

Scene& Scene::add(const Shape& shape) {
  shapes_.push_back(shape);
  return *this;
}

std::optional<Hit> Scene::intersect(const Vec3& origin, const Vec3& dir) const {
  std::optional<double> best;
  const Shape* best_shape = nullptr;
  for (const auto& shape : shapes_) {
    const auto t = std::visit([&](const auto& s) { return hit(s, origin, dir); }, shape);
    if (t && (!best || *t < *best)) best = t, best_shape = &shape;
  }
  if (!best) return std::nullopt;
  Hit h;
  h.point = origin + *best * dir;
  h.normal = std::visit(
      [&](const auto& s) -> Vec3 {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Plane>) {
          return s.normal.normalized();
        } else if constexpr (std::is_same_v<S, Sphere>) {
          return (h.point - s.centre).normalized();
        } else {
          return Vec3(h.point.x() - s.centre.x(), h.point.y() - s.centre.y(), 0).normalized();
        }
      },
      *best_shape);
  if (h.normal.dot(dir) > 0) h.normal = -h.normal;
  return h;
}

Vec3 Scene::colour(const Hit& h) const {
  const Vec3 base = texture(h.point);
  if (!decorated_) return base;
  // Half the contrast around a warm grey, soft dark lines on a 1 m grid, light from above.
  Vec3 c = 0.5 * base + 0.5 * Vec3(150, 160, 170);
  double line = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(h.normal[axis]) > 0.9) continue;  // no lines across the surface's own normal
    const double f = h.point[axis] - std::floor(h.point[axis]);
    const double d = std::min(f, 1 - f);
    line = std::max(line, std::exp(-(d * d) / (2 * 0.015 * 0.015)));
  }
  const double light = 0.65 + 0.35 * std::abs(h.normal.dot(Vec3(0.3, 0.2, 0.93).normalized()));
  return (c * (1 - 0.7 * line)) * light;
}

Vec3 Scene::texture(const Vec3& p) {
  const double k = 2 * M_PI;
  // Wavelengths from 1.1 m down to 0.2 m: coarse enough to resample cleanly, fine enough
  // that one pixel of misregistration at a few metres shows.
  const double b = 128 + 50 * std::sin(k * (0.9 * p.x() + 0.35 * p.y() + 0.2 * p.z())) +
                   35 * std::sin(k * (1.7 * p.y() - 0.6 * p.z())) + 30 * std::sin(k * (4.1 * p.x() + 2.3 * p.z()));
  const double g = 128 + 50 * std::sin(k * (0.5 * p.x() - 1.1 * p.y() + 0.3 * p.z()) + 1.0) +
                   35 * std::cos(k * (1.3 * p.z() + 0.4 * p.x())) + 30 * std::cos(k * (3.7 * p.y() - 2.9 * p.x()));
  const double r = 128 + 50 * std::cos(k * (1.2 * p.x() + 0.8 * p.z())) +
                   35 * std::sin(k * (0.7 * p.y() + 1.5 * p.z()) + 2.0) + 30 * std::sin(k * (4.4 * p.z() + 1.9 * p.y()));
  return Vec3(std::clamp(b, 0.0, 255.0), std::clamp(g, 0.0, 255.0), std::clamp(r, 0.0, 255.0));
}

Scene Scene::room() {
  Scene s;
  s.decorated();
  s.add(Plane{Vec3::UnitZ(), 0.0})     // floor
      .add(Plane{Vec3::UnitZ(), 3.0})  // ceiling
      .add(Plane{Vec3::UnitX(), 4.5})
      .add(Plane{Vec3::UnitX(), -3.5})
      .add(Plane{Vec3::UnitY(), 3.0})
      .add(Plane{Vec3::UnitY(), -2.5})
      .add(Cylinder{Vec3(2.0, 1.2, 0), 0.25, 0.0, 3.0})
      .add(Cylinder{Vec3(-1.5, -1.4, 0), 0.3, 0.0, 3.0});
  return s;
}

}  // namespace omniview::synthetic
