// Renderable geometry: unindexed triangles with per-vertex normals and colours.
//
// Unindexed because everything we draw comes from primitives with flat faces and from
// mesh files whose normals are per face anyway; the renderer hands the arrays to GL as is.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace omniview::robot {

using Rgba8 = std::array<uint8_t, 4>;

// Colour from URDF-style floats in [0, 1] (clamped).
Rgba8 rgba8(float r, float g, float b, float a = 1.0f);

struct TriangleMesh {
  // Three consecutive entries per triangle; all three arrays have the same length.
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;
  std::vector<Rgba8> colours;

  size_t triangle_count() const { return positions.size() / 3; }
  void add_triangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                    const Eigen::Vector3f& normal, const Rgba8& colour);
  void append(const TriangleMesh& other);
  void set_colour(const Rgba8& colour);
  // Smallest sphere centred at the box centre that holds every vertex (renderer depth range).
  void bounding_sphere(Eigen::Vector3f& centre, float& radius) const;
  // Whether `p` lies inside the mesh's axis-aligned bounding box.
  bool box_contains(const Eigen::Vector3f& p) const;
};

}  // namespace omniview::robot
