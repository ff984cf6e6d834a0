// The form of listen addresses as gRPC takes them (who can reach one is the exposure
// rule's business: server/exposure).
#include <arpa/inet.h>

#include <algorithm>
#include <cctype>

#include "server/config/daemon_config.h"
#include "server/exposure/host_port.h"

namespace omniview {

std::string listen_address_problem(const std::string& listen) {
  if (listen.empty()) return "is empty (expected host:port, e.g. 127.0.0.1:50051)";
  if (is_unix_address(listen)) {
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

}  // namespace omniview
