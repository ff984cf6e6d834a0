#include "core/view/view_keys.h"

#include <algorithm>

namespace omniview {

const std::vector<std::string>& surface_keys() {
  static const std::vector<std::string> keys{"hfov_deg",         "distance",    "height_m",    "ground_z", "radius",
                                             "vfov_deg",         "azimuth_span_deg", "lat_min_deg", "lat_max_deg",
                                             "fov_deg"};
  return keys;
}

const std::vector<std::string>& surface_keys(ViewType type) {
  // As view_to_yaml writes them and View::create reads them.
  // ground_z: every type's, the plane that `ground: true` cuts the surface with.
  static const std::vector<std::string> perspective{"hfov_deg", "distance", "ground_z"};
  static const std::vector<std::string> birdseye{"hfov_deg", "height_m", "ground_z"};
  static const std::vector<std::string> cylindrical{"radius", "vfov_deg", "azimuth_span_deg", "ground_z"};
  static const std::vector<std::string> latitudes{"radius", "azimuth_span_deg", "lat_min_deg", "lat_max_deg", "ground_z"};
  static const std::vector<std::string> fisheye{"radius", "fov_deg", "ground_z"};
  switch (type) {
    case ViewType::kPerspective: return perspective;
    case ViewType::kBirdseye: return birdseye;
    case ViewType::kCylindrical: return cylindrical;
    case ViewType::kMercator:
    case ViewType::kEquirectangular: return latitudes;
    case ViewType::kFisheye: return fisheye;
  }
  return perspective;
}

std::string inapplicable_key(const std::string& key, ViewType type) {
  const auto& all = surface_keys();
  const auto& mine = surface_keys(type);
  if (std::find(all.begin(), all.end(), key) == all.end()) return "";
  if (std::find(mine.begin(), mine.end(), key) != mine.end()) return "";
  std::string list;
  for (const auto& k : mine) list += (list.empty() ? "" : ", ") + k;
  if (type != ViewType::kBirdseye) list += ", ground";  // a switch, not a surface length
  return key + " does not apply to " + to_string(type) + " views (their keys: " + list + ")";
}

}  // namespace omniview
