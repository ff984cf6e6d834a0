// `omniview views save FILE`: the daemon's current views as a YAML file its `views_file:`
// config key loads at start, so views created or changed at run time survive a restart.
#pragma once

#include <string>

#include "cli/client/connection.h"

namespace omniview::cli {

// Writes every view of the daemon (as ListViews returns them) to `file` under `views:`,
// replacing the file atomically; returns the number of views written.
int save_views(Connection& connection, const std::string& file);

}  // namespace omniview::cli
