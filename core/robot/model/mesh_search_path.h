// Where mesh files named in a URDF are found.
//
//   package://NAME/rest  ->  FOLDER/NAME/rest, then FOLDER/rest, for each search folder in order
//   file:///abs/path      ->  /abs/path
//   /abs/path             ->  as is
//   relative/path         ->  next to the URDF first, then FOLDER/relative/path
//
// A URI that resolves nowhere is an error naming the URI, every path tried and the search path.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace omniview::robot {

class MeshSearchPath {
 public:
  MeshSearchPath() = default;
  explicit MeshSearchPath(std::vector<std::filesystem::path> folders) : folders_(std::move(folders)) {}

  const std::vector<std::filesystem::path>& folders() const { return folders_; }

  // Existing file for `uri`, referenced from the URDF in `urdf_dir`. Throws
  // std::runtime_error (see above) when there is none.
  std::filesystem::path resolve(const std::string& uri, const std::filesystem::path& urdf_dir) const;

  // The paths `uri` may mean, in the order they are tried.
  std::vector<std::filesystem::path> candidates(const std::string& uri, const std::filesystem::path& urdf_dir) const;

 private:
  std::vector<std::filesystem::path> folders_;
};

}  // namespace omniview::robot
