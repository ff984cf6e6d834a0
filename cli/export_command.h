#pragma once

#include <string>
#include <vector>

namespace omniview::cli {

// `omniview export RECORDING -o FILE.mcap`: a recording as an MCAP file (server/export).
int export_command(const std::vector<std::string>& args);

}  // namespace omniview::cli
