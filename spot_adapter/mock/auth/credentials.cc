#include "spot_adapter/mock/auth/credentials.h"

#include <fcntl.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "spot_adapter/mock/auth/random_text.h"

namespace omniview::spot_mock {
namespace {

void create(const std::string& path) {
  const Credentials fresh{"user", random_alphanumeric(16)};
  const std::string text = "# spot-mock login (created by spot-mock)\nusername: " + fresh.username +
                           "\npassword: " + fresh.password + "\n";
  // O_EXCL with 0600: the password is never readable by others, not even for a moment.
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0) throw std::runtime_error("cannot create credentials file " + path);
  const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  ::close(fd);
  if (!ok) throw std::runtime_error("cannot write credentials file " + path);
}

}  // namespace

Credentials load_or_create_credentials(const std::string& path, bool* created) {
  if (created) *created = false;
  if (!std::filesystem::exists(path)) {
    create(path);
    if (created) *created = true;
  }
  try {
    const YAML::Node root = YAML::LoadFile(path);
    Credentials c;
    if (root["username"]) c.username = root["username"].as<std::string>();
    if (root["password"]) c.password = root["password"].as<std::string>();
    if (c.username.empty() || c.password.empty()) {
      throw std::runtime_error(path + ": needs both `username` and `password`");
    }
    return c;
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace omniview::spot_mock
