// Listen addresses as gRPC takes them, and whether one is reachable only from this machine
// (which decides whether plaintext without tokens is acceptable).
#include <arpa/inet.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <optional>

#include "server/config/daemon_config.h"

namespace omniview {
namespace {

bool starts_with_unix_scheme(const std::string& listen) {
  return listen.rfind("unix:", 0) == 0 || listen.rfind("unix-abstract:", 0) == 0;
}

struct HostPort {
  std::string host;
  std::string port;
  bool bracketed = false;
};

// "host:port" or "[v6]:port"; nullopt when the shape is wrong.
std::optional<HostPort> split_host_port(const std::string& listen) {
  HostPort hp;
  if (!listen.empty() && listen.front() == '[') {
    const auto close = listen.find(']');
    if (close == std::string::npos || close + 1 >= listen.size() || listen[close + 1] != ':') return std::nullopt;
    hp.host = listen.substr(1, close - 1);
    hp.port = listen.substr(close + 2);
    hp.bracketed = true;
    return hp;
  }
  const auto colon = listen.rfind(':');
  if (colon == std::string::npos) return std::nullopt;
  hp.host = listen.substr(0, colon);
  hp.port = listen.substr(colon + 1);
  return hp;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

}  // namespace

std::string listen_address_problem(const std::string& listen) {
  if (listen.empty()) return "is empty (expected host:port, e.g. 127.0.0.1:50051)";
  if (starts_with_unix_scheme(listen)) {
    return listen.substr(listen.find(':') + 1).empty() ? "names no socket path (expected unix:/path/to/socket)" : "";
  }
  const auto hp = split_host_port(listen);
  if (!hp) return "'" + listen + "' is not host:port (e.g. 127.0.0.1:50051, [::1]:50051 or unix:/path)";
  if (!hp->bracketed && hp->host.find(':') != std::string::npos) {
    return "'" + listen + "': put an IPv6 address in brackets, e.g. [::1]:50051";
  }
  if (hp->host.empty()) return "'" + listen + "' names no host (use 0.0.0.0 or [::] for every interface)";
  in6_addr v6;
  if (hp->bracketed && inet_pton(AF_INET6, hp->host.c_str(), &v6) != 1) {
    return "'" + hp->host + "' is not an IPv6 address";
  }
  const bool digits = !hp->port.empty() && hp->port.size() <= 5 &&
                      std::all_of(hp->port.begin(), hp->port.end(), [](unsigned char c) { return std::isdigit(c); });
  if (!digits || std::stoi(hp->port) > 65535) {
    return "'" + listen + "': the port must be a number from 0 to 65535 (0 picks a free one)";
  }
  return "";
}

bool is_loopback_address(const std::string& listen) {
  if (starts_with_unix_scheme(listen)) return true;  // a socket file is not on the network
  const auto hp = split_host_port(listen);
  if (!hp) return false;
  if (lower(hp->host) == "localhost") return true;
  in_addr v4;
  if (inet_pton(AF_INET, hp->host.c_str(), &v4) == 1) {
    return (ntohl(v4.s_addr) >> 24) == 127;
  }
  in6_addr v6;
  if (inet_pton(AF_INET6, hp->host.c_str(), &v6) == 1) {
    if (IN6_IS_ADDR_LOOPBACK(&v6)) return true;
    return IN6_IS_ADDR_V4MAPPED(&v6) && v6.s6_addr[12] == 127;  // ::ffff:127.x.y.z
  }
  return false;  // a host name or a wildcard (0.0.0.0, [::]): reachable from elsewhere
}

}  // namespace omniview
