// What surfaces look like: the test texture and the materials that dress it up.
#include <algorithm>
#include <cmath>

#include "core/synthetic/scene.h"

namespace omniview::synthetic {
namespace {

// Distance-to-line profile of soft dark lines every `period` metres along the axes that
// run across the surface (not along its normal): 1 on a line, falling to 0 within ~3 cm,
// so the lines stay smooth enough to resample.
double grid_line(const Vec3& p, const Vec3& normal, double period) {
  double line = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(normal[axis]) > 0.9) continue;
    const double f = p[axis] / period - std::floor(p[axis] / period);
    const double d = std::min(f, 1 - f) * period;
    line = std::max(line, std::exp(-(d * d) / (2 * 0.015 * 0.015)));
  }
  return line;
}

// A soft checker in [-1, 1] over the two axes most in the surface's plane.
double checker(const Vec3& p, const Vec3& normal, double period) {
  int a = 0, b = 1;
  const int along_normal = [&] {
    int i = 0;
    normal.cwiseAbs().maxCoeff(&i);
    return i;
  }();
  if (along_normal == 0) a = 1, b = 2;
  if (along_normal == 1) a = 0, b = 2;
  const double s = std::sin(M_PI * p[a] / period) * std::sin(M_PI * p[b] / period);
  return std::tanh(4 * s);
}

}  // namespace

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

Vec3 Scene::colour(const Hit& h) const {
  const Material& m = materials_.at(h.shape);
  Vec3 c = texture(h.point);
  if (m.texture_contrast != 1) c = m.base + m.texture_contrast * (c - m.base);
  if (m.tiles_m > 0) c *= 1 + 0.25 * checker(h.point, h.normal, m.tiles_m);
  if (m.grid_m > 0) c *= 1 - 0.7 * grid_line(h.point, h.normal, m.grid_m);
  if (m.lit) c *= 0.65 + 0.35 * std::abs(h.normal.dot(Vec3(0.3, 0.2, 0.93).normalized()));
  return c.cwiseMax(0.0).cwiseMin(255.0);
}

}  // namespace omniview::synthetic
