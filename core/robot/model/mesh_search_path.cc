#include "core/robot/model/mesh_search_path.h"

#include <sstream>
#include <stdexcept>

namespace omniview::robot {
namespace fs = std::filesystem;

namespace {

bool starts_with(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

}  // namespace

std::vector<fs::path> MeshSearchPath::candidates(const std::string& uri, const fs::path& urdf_dir) const {
  std::vector<fs::path> out;
  if (starts_with(uri, "package://")) {
    const std::string rest = uri.substr(10);
    const size_t slash = rest.find('/');
    const std::string package = rest.substr(0, slash);
    const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
    for (const auto& folder : folders_) {
      out.push_back(folder / package / inside);
      out.push_back(folder / inside);
    }
  } else if (starts_with(uri, "file://")) {
    out.emplace_back(uri.substr(7));
  } else if (fs::path(uri).is_absolute()) {
    out.emplace_back(uri);
  } else {
    out.push_back(urdf_dir / uri);
    for (const auto& folder : folders_) out.push_back(folder / uri);
  }
  return out;
}

fs::path MeshSearchPath::resolve(const std::string& uri, const fs::path& urdf_dir) const {
  // Other URI schemes (http://, model://) are not read from the network or elsewhere:
  // say so rather than look for a file called "http:".
  const size_t scheme = uri.find("://");
  if (scheme != std::string::npos && !starts_with(uri, "package://") && !starts_with(uri, "file://")) {
    throw std::runtime_error("mesh '" + uri + "': only package://, file:// and file paths are supported (download it "
                             "and point mesh_path at its folder)");
  }
  const auto tried = candidates(uri, urdf_dir);
  for (const auto& p : tried) {
    std::error_code ec;
    if (fs::is_regular_file(p, ec)) return p;
  }
  std::ostringstream msg;  // (a stream: GCC 12 warns falsely about `" " + path` at -O3)
  msg << "mesh '" << uri << "' not found; tried:";
  for (const auto& p : tried) msg << ' ' << p.string();
  if (tried.empty()) msg << " nothing";
  msg << "; mesh search path:";
  for (const auto& f : folders_) msg << ' ' << f.string();
  if (folders_.empty()) msg << " (empty)";
  throw std::runtime_error(msg.str());
}

}  // namespace omniview::robot
