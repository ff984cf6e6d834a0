// The one user spot-mock accepts, kept in a YAML file {username: ..., password: ...}.
#pragma once

#include <string>

namespace omniview::spot_mock {

struct Credentials {
  std::string username;
  std::string password;
};

// Reads `path`; if it does not exist, first creates it (mode 0600) with username "user" and
// a random 16-character password, and sets *created. Throws std::runtime_error naming the
// file when it cannot be read, written, or lacks either key.
Credentials load_or_create_credentials(const std::string& path, bool* created = nullptr);

}  // namespace omniview::spot_mock
