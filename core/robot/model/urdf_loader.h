// Robot models from URDF (urdfdom), with the visual geometry of every link.
//
// Visuals: box, cylinder, sphere and mesh (any format assimp reads: STL, OBJ, DAE, ...),
// with the visual's origin and the mesh's scale applied. Colour: the URDF material's colour
// where the URDF gives one (inline or by name), else each sub-mesh's diffuse colour from
// the mesh file, else grey. Material textures are not drawn. Collision geometry is ignored.
#pragma once

#include <filesystem>
#include <string>

#include "core/robot/model/mesh_search_path.h"
#include "core/robot/model/robot_model.h"

namespace omniview::robot {

// Throws std::runtime_error naming the file (and urdfdom's reason) for an unreadable or
// malformed URDF, and naming the URI and the search path for a mesh that is not found.
RobotModel load_urdf_file(const std::filesystem::path& urdf, const MeshSearchPath& search_path = {});

// The same for URDF text; relative mesh URIs resolve against `urdf_dir`; `what` names the
// text in error messages.
RobotModel load_urdf_string(const std::string& xml, const std::filesystem::path& urdf_dir,
                            const MeshSearchPath& search_path, const std::string& what);

}  // namespace omniview::robot
