// URDF primitive shapes as triangle meshes, centred at the origin of their visual frame
// (URDF: a box is centred, a cylinder's axis is z). Colour is filled in by the caller.
#pragma once

#include "core/robot/model/triangle_mesh.h"

namespace omniview::robot {

// Flat-shaded box with the given edge lengths.
TriangleMesh make_box(const Eigen::Vector3f& size);
// Cylinder along z, length `length`, with flat caps; `segments` around the axis.
TriangleMesh make_cylinder(float radius, float length, int segments = 32);
// UV sphere with smooth normals.
TriangleMesh make_sphere(float radius, int slices = 24, int stacks = 12);

}  // namespace omniview::robot
