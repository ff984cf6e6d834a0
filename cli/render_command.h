// `omniview render`: one or more views computed offline from a rig and image files.
#pragma once

#include <string>
#include <vector>

namespace omniview::cli {

int render_command(const std::vector<std::string>& args);

}  // namespace omniview::cli
