// Mesh files (STL, OBJ, DAE and whatever else assimp reads) as one triangle mesh.
//
// Node transforms are applied, so the mesh is in the file's root frame, scaled by `scale`.
// Collada's unit (<unit meter=...>) is honoured, its up axis is not: as in ROS, a DAE's
// coordinates are taken as the link's, whatever <up_axis> says.
// Colours are each sub-mesh's diffuse material colour, `fallback` where the file has none.
#pragma once

#include <filesystem>

#include "core/robot/model/triangle_mesh.h"

namespace omniview::robot {

// Throws std::runtime_error naming the file and assimp's reason.
TriangleMesh load_mesh_file(const std::filesystem::path& path, const Eigen::Vector3f& scale, const Rgba8& fallback);

}  // namespace omniview::robot
