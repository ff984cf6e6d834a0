// The robot user's name and password. They come from a file or the environment, never
// from the command line (visible in `ps`) and never into logs.
#pragma once

#include <string>

namespace omniview::spot {

struct Credentials {
  std::string username;
  std::string password;
};

// Environment variables the Boston Dynamics SDKs read too, so an existing setup works.
inline constexpr const char* kUsernameEnv = "BOSDYN_CLIENT_USERNAME";
inline constexpr const char* kPasswordEnv = "BOSDYN_CLIENT_PASSWORD";

// From `file` (YAML: `username: ...`, `password: ...`) when it is not empty, else from
// the environment. Read again at every login, so fixing the file needs no restart.
// Throws SpotError(kCredentials) naming the file or the variables (never the password).
Credentials load_credentials(const std::string& file);

}  // namespace omniview::spot
