#include "spot_adapter/client/credentials.h"

#include <cstdlib>

#include <yaml-cpp/yaml.h>

#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {
namespace {

[[noreturn]] void fail(const std::string& message) { throw SpotError(SpotError::Kind::kCredentials, message); }

}  // namespace

Credentials load_credentials(const std::string& file) {
  Credentials c;
  if (file.empty()) {
    const char* user = std::getenv(kUsernameEnv);
    const char* password = std::getenv(kPasswordEnv);
    if (!user || !*user || !password) {
      fail(std::string("no robot credentials: set credentials_file in the source's config, or the environment "
                       "variables ") + kUsernameEnv + " and " + kPasswordEnv);
    }
    c.username = user;
    c.password = password;
    return c;
  }
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    fail("cannot read the credentials file '" + file + "'");
  } catch (const YAML::Exception& e) {
    // The parser's message may quote the file's text, which holds the password: leave it out.
    fail("the credentials file '" + file + "' is not valid YAML (line " + std::to_string(e.mark.line + 1) + ")");
  }
  if (!root.IsMap()) fail("the credentials file '" + file + "' must be a map with `username` and `password`");
  for (const char* key : {"username", "password"}) {
    if (!root[key] || !root[key].IsScalar() || root[key].Scalar().empty()) {
      fail("the credentials file '" + file + "' has no `" + key + "`");
    }
  }
  c.username = root["username"].Scalar();
  c.password = root["password"].Scalar();
  return c;
}

}  // namespace omniview::spot
