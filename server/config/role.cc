// Token roles: a viewer streams and reads, an operator may also change views.
#include <stdexcept>

#include "server/config/daemon_config.h"

namespace omniview {

std::string to_string(Role role) { return role == Role::kOperator ? "operator" : "viewer"; }

Role role_from_string(const std::string& name) {
  if (name == "viewer") return Role::kViewer;
  if (name == "operator") return Role::kOperator;
  throw std::invalid_argument("unknown role '" + name + "' (expected viewer or operator)");
}

bool role_allows(Role granted, Role needed) { return granted == Role::kOperator || needed == Role::kViewer; }

}  // namespace omniview
