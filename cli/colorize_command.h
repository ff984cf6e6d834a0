// `omniview colorize`: colours a point cloud file offline from a rig and one image per camera.
#pragma once

#include <string>
#include <vector>

namespace omniview::cli {

int colorize_command(const std::vector<std::string>& args);

}  // namespace omniview::cli
