#include "core/robot/model/mesh_loader.h"

#include <stdexcept>

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

namespace omniview::robot {
namespace {

Rgba8 diffuse_colour(const aiScene& scene, unsigned material_index, const Rgba8& fallback) {
  if (material_index >= scene.mNumMaterials) return fallback;
  aiColor4D c;
  if (aiGetMaterialColor(scene.mMaterials[material_index], AI_MATKEY_COLOR_DIFFUSE, &c) != AI_SUCCESS) return fallback;
  return rgba8(c.r, c.g, c.b, c.a);
}

}  // namespace

TriangleMesh load_mesh_file(const std::filesystem::path& path, const Eigen::Vector3f& scale, const Rgba8& fallback) {
  Assimp::Importer importer;
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // Points and lines are not surfaces; drop them rather than draw them.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const unsigned flags = aiProcess_Triangulate | aiProcess_GenNormals | aiProcess_PreTransformVertices |
                         aiProcess_SortByPType | aiProcess_FindDegenerates;
  const aiScene* scene = importer.ReadFile(path.string(), flags);
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    throw std::runtime_error("cannot read mesh " + path.string() + ": " + importer.GetErrorString());
  }
  // The assimp built-in material of files without one has a grey diffuse colour, which would
  // hide the URDF's fallback; only trust materials the file defines.
  const bool file_has_materials = !(scene->mNumMaterials == 1 && scene->mMaterials[0]->GetName() == aiString(AI_DEFAULT_MATERIAL_NAME));

  TriangleMesh mesh;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh& in = *scene->mMeshes[m];
    if (!(in.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || !in.HasNormals()) continue;
    const Rgba8 colour = file_has_materials ? diffuse_colour(*scene, in.mMaterialIndex, fallback) : fallback;
    for (unsigned f = 0; f < in.mNumFaces; ++f) {
      const aiFace& face = in.mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (unsigned k = 0; k < 3; ++k) {
        const aiVector3D& p = in.mVertices[face.mIndices[k]];
        const aiVector3D& n = in.mNormals[face.mIndices[k]];
        mesh.positions.emplace_back(p.x * scale.x(), p.y * scale.y(), p.z * scale.z());
        // Normals transform with the inverse transpose of the (diagonal) scale.
        mesh.normals.push_back(Eigen::Vector3f(n.x / scale.x(), n.y / scale.y(), n.z / scale.z()).normalized());
        mesh.colours.push_back(colour);
      }
    }
  }
  if (mesh.positions.empty()) throw std::runtime_error("mesh " + path.string() + " has no triangles");
  return mesh;
}

}  // namespace omniview::robot
