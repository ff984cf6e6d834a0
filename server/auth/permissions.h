// Who may do what, for every way into the daemon, in one table: each RPC of
// omniview.v1.Omniview, each op of the console's WebSocket, the Foxglove WebSocket and
// RTSP. The gRPC handlers and the console's calls look their role up here (nowhere else
// says it), and a test checks the table against the service's descriptor and the
// console's ops, so a new RPC or op cannot go unlisted.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "server/config/daemon_config.h"

namespace omniview::permissions {

struct Permission {
  std::string_view request;  // "omniview.v1.Omniview/GetView", "console:subscribe", "rtsp", ...
  Role role;                 // the least role a token needs (without tokens, everybody may)
};

// Every request of every front end.
const std::vector<Permission>& all();

// The role `request` needs; nullopt for a request the table does not list.
std::optional<Role> role_for(std::string_view request);

// The role an RPC of omniview.v1.Omniview needs, by method name ("GetView"). Throws
// std::logic_error for a method the table lacks: a programming error, found by the tests.
Role rpc_role(std::string_view method);

inline constexpr std::string_view kServicePrefix = "omniview.v1.Omniview/";

}  // namespace omniview::permissions
