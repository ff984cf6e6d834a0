// "host:port" and "[v6]:port" as gRPC's listeners take them, split once for every user
// (the config's form check, the exposure rule).
#pragma once

#include <optional>
#include <string>

namespace omniview {

struct HostPort {
  std::string host;
  std::string port;
  bool bracketed = false;  // "[v6]:port"
};

// nullopt when the shape is wrong (no colon, an unclosed bracket); unix: addresses are not
// host:port and give nullopt too.
std::optional<HostPort> split_host_port(const std::string& address);

// "unix:" or "unix-abstract:" addresses.
bool is_unix_address(const std::string& address);

}  // namespace omniview
