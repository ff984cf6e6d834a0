#include "core/robot/model/triangle_mesh.h"

#include <algorithm>
#include <cmath>

namespace omniview::robot {

Rgba8 rgba8(float r, float g, float b, float a) {
  const auto byte = [](float x) { return static_cast<uint8_t>(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f)); };
  return {byte(r), byte(g), byte(b), byte(a)};
}

void TriangleMesh::add_triangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                                const Eigen::Vector3f& normal, const Rgba8& colour) {
  for (const auto* p : {&a, &b, &c}) {
    positions.push_back(*p);
    normals.push_back(normal);
    colours.push_back(colour);
  }
}

void TriangleMesh::append(const TriangleMesh& other) {
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  normals.insert(normals.end(), other.normals.begin(), other.normals.end());
  colours.insert(colours.end(), other.colours.begin(), other.colours.end());
}

void TriangleMesh::set_colour(const Rgba8& colour) { std::fill(colours.begin(), colours.end(), colour); }

bool TriangleMesh::box_contains(const Eigen::Vector3f& p) const {
  if (positions.empty()) return false;
  Eigen::Vector3f lo = positions[0], hi = positions[0];
  for (const auto& q : positions) {
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
}

void TriangleMesh::bounding_sphere(Eigen::Vector3f& centre, float& radius) const {
  if (positions.empty()) {
    centre.setZero();
    radius = 0;
    return;
  }
  Eigen::Vector3f lo = positions[0], hi = positions[0];
  for (const auto& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  centre = 0.5f * (lo + hi);
  float r2 = 0;
  for (const auto& p : positions) r2 = std::max(r2, (p - centre).squaredNorm());
  radius = std::sqrt(r2);
}

}  // namespace omniview::robot
