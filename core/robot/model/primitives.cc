#include "core/robot/model/primitives.h"

#include <cmath>

namespace omniview::robot {
namespace {

using V3 = Eigen::Vector3f;
const Rgba8 kWhite{255, 255, 255, 255};

// One smooth-shaded triangle: the normal at each vertex is given separately.
void add_smooth(TriangleMesh& m, const V3& a, const V3& na, const V3& b, const V3& nb, const V3& c, const V3& nc) {
  m.positions.insert(m.positions.end(), {a, b, c});
  m.normals.insert(m.normals.end(), {na, nb, nc});
  m.colours.insert(m.colours.end(), {kWhite, kWhite, kWhite});
}

}  // namespace

TriangleMesh make_box(const V3& size) {
  TriangleMesh m;
  const V3 h = 0.5f * size;
  // For each axis and sign: the face whose outward normal is that signed axis.
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // (u, v, axis) is right-handed
    for (const float sign : {-1.0f, 1.0f}) {
      V3 n = V3::Zero();
      n[axis] = sign;
      V3 corner[4];
      const float su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
      for (int k = 0; k < 4; ++k) {
        corner[k][axis] = sign * h[axis];
        corner[k][u] = su[k] * h[u];
        corner[k][v] = sv[k] * h[v];
      }
      // Counter-clockwise seen from outside: reverse the order on the negative face.
      if (sign > 0) {
        m.add_triangle(corner[0], corner[1], corner[2], n, kWhite);
        m.add_triangle(corner[0], corner[2], corner[3], n, kWhite);
      } else {
        m.add_triangle(corner[0], corner[2], corner[1], n, kWhite);
        m.add_triangle(corner[0], corner[3], corner[2], n, kWhite);
      }
    }
  }
  return m;
}

TriangleMesh make_cylinder(float radius, float length, int segments) {
  TriangleMesh m;
  const float z = 0.5f * length;
  const V3 up(0, 0, 1), down(0, 0, -1);
  for (int i = 0; i < segments; ++i) {
    const float a0 = 2.0f * float(M_PI) * float(i) / float(segments);
    const float a1 = 2.0f * float(M_PI) * float(i + 1) / float(segments);
    const V3 n0(std::cos(a0), std::sin(a0), 0), n1(std::cos(a1), std::sin(a1), 0);
    const V3 b0 = radius * n0 - V3(0, 0, z), b1 = radius * n1 - V3(0, 0, z);
    const V3 t0 = radius * n0 + V3(0, 0, z), t1 = radius * n1 + V3(0, 0, z);
    add_smooth(m, b0, n0, b1, n1, t1, n1);
    add_smooth(m, b0, n0, t1, n1, t0, n0);
    m.add_triangle(V3(0, 0, z), t0, t1, up, kWhite);
    m.add_triangle(V3(0, 0, -z), b1, b0, down, kWhite);
  }
  return m;
}

TriangleMesh make_sphere(float radius, int slices, int stacks) {
  TriangleMesh m;
  const auto unit = [&](int i, int j) {
    const float theta = float(M_PI) * float(j) / float(stacks);  // from the north pole
    const float phi = 2.0f * float(M_PI) * float(i) / float(slices);
    return V3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  };
  for (int j = 0; j < stacks; ++j) {
    for (int i = 0; i < slices; ++i) {
      const V3 a = unit(i, j), b = unit(i, j + 1), c = unit(i + 1, j + 1), d = unit(i + 1, j);
      if (j > 0) add_smooth(m, radius * a, a, radius * b, b, radius * d, d);
      if (j + 1 < stacks) add_smooth(m, radius * b, b, radius * c, c, radius * d, d);
    }
  }
  return m;
}

}  // namespace omniview::robot
