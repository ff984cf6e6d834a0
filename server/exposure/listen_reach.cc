// Who can reach a listen address: loopback numbers, host names resolved the way the
// listener resolves them, and unix sockets by their folder's permissions.
#include <arpa/inet.h>
#include <netdb.h>
#include <sys/socket.h>
#include <sys/stat.h>

#include <cstdio>
#include <stdexcept>
#include <filesystem>

#include "server/exposure/exposure_rule.h"
#include "server/exposure/host_port.h"

namespace omniview {
namespace {

// 127.0.0.0/8, ::1 and ::ffff:127.x.y.z. Wildcards (0.0.0.0, ::, ::ffff:0.0.0.0) and every
// other number reach beyond this machine.
bool is_loopback_number(const std::string& numeric) {
  in_addr v4;
  if (inet_pton(AF_INET, numeric.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6;
  if (inet_pton(AF_INET6, numeric.c_str(), &v6) == 1) {
    if (IN6_IS_ADDR_LOOPBACK(&v6)) return true;
    return IN6_IS_ADDR_V4MAPPED(&v6) && v6.s6_addr[12] == 127;
  }
  return false;
}

std::string octal_mode(mode_t mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

Reach unix_socket_reach(const std::string& address) {
  if (address.rfind("unix-abstract:", 0) == 0) {
    // Abstract sockets have no file and no permissions: every process on the machine may connect.
    return {false, true, "the abstract unix socket '" + address + "' has no permissions: every user of this machine can connect"};
  }
  const std::filesystem::path socket(unix_socket_path(address));
  std::filesystem::path folder = socket.parent_path();
  if (folder.empty()) folder = ".";
  struct stat st {};
  if (::stat(folder.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
    return {false, false, "the folder '" + folder.string() + "' of unix socket '" + socket.string() + "' does not exist"};
  }
  if ((st.st_mode & S_IRWXO) != 0) {
    return {false, true,
            "the unix socket '" + socket.string() + "' lies in folder '" + folder.string() + "' (mode " +
                octal_mode(st.st_mode) + ") that every user of this machine can enter"};
  }
  return {true, true, ""};
}

}  // namespace

bool is_unix_address(const std::string& address) {
  return address.rfind("unix:", 0) == 0 || address.rfind("unix-abstract:", 0) == 0;
}

std::string unix_socket_path(const std::string& address) {
  if (address.rfind("unix:", 0) != 0) return "";
  std::string path = address.substr(5);
  if (path.rfind("///", 0) == 0) path.erase(0, 2);  // unix:///abs/path, the URI form
  return path;
}

std::optional<HostPort> split_host_port(const std::string& address) {
  if (is_unix_address(address)) return std::nullopt;
  HostPort hp;
  if (!address.empty() && address.front() == '[') {
    const auto close = address.find(']');
    if (close == std::string::npos || close + 1 >= address.size() || address[close + 1] != ':') return std::nullopt;
    hp.host = address.substr(1, close - 1);
    hp.port = address.substr(close + 2);
    hp.bracketed = true;
    return hp;
  }
  const auto colon = address.rfind(':');
  if (colon == std::string::npos) return std::nullopt;
  hp.host = address.substr(0, colon);
  hp.port = address.substr(colon + 1);
  return hp;
}

std::vector<std::string> resolve_host(const std::string& host, std::string* error) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;  // as a listener resolves it
  addrinfo* found = nullptr;
  const int rc = ::getaddrinfo(host.c_str(), nullptr, &hints, &found);
  std::vector<std::string> out;
  if (rc != 0) {
    if (error) *error = gai_strerror(rc);
    return out;
  }
  for (const addrinfo* a = found; a; a = a->ai_next) {
    char text[INET6_ADDRSTRLEN] = {};
    const void* number = a->ai_family == AF_INET
                             ? static_cast<const void*>(&reinterpret_cast<const sockaddr_in*>(a->ai_addr)->sin_addr)
                             : static_cast<const void*>(&reinterpret_cast<const sockaddr_in6*>(a->ai_addr)->sin6_addr);
    if ((a->ai_family == AF_INET || a->ai_family == AF_INET6) && inet_ntop(a->ai_family, number, text, sizeof text)) {
      out.emplace_back(text);
    }
  }
  ::freeaddrinfo(found);
  if (out.empty() && error) *error = "no IPv4 or IPv6 address";
  return out;
}

Reach listen_reach(const std::string& address, const HostResolver& resolve) {
  if (is_unix_address(address)) return unix_socket_reach(address);
  const auto hp = split_host_port(address);
  if (!hp) return {false, false, "'" + address + "' is not host:port"};
  const std::string remote = "'" + address + "' is reachable from other machines";
  if (hp->host.empty()) return {false, true, remote + " (an empty host means every interface)"};
  // A number in any spelling the listener accepts (0, 0x7f.1, [::ffff:0.0.0.0]) is
  // classified by what it resolves to, never by how it is written.
  in6_addr v6;
  in_addr v4;
  const bool numeric = inet_pton(AF_INET6, hp->host.c_str(), &v6) == 1 || inet_pton(AF_INET, hp->host.c_str(), &v4) == 1;
  std::vector<std::string> numbers;
  if (numeric) {
    numbers.push_back(hp->host);
  } else {
    std::string error;
    numbers = resolve ? resolve(hp->host, &error) : resolve_host(hp->host, &error);
    if (numbers.empty()) return {false, false, "host '" + hp->host + "' in '" + address + "' does not resolve: " + error};
  }
  for (const auto& n : numbers) {
    if (!is_loopback_number(n)) {
      if (n == hp->host) return {false, true, remote};
      return {false, true, remote + " (host '" + hp->host + "' stands for " + n + ")"};
    }
  }
  return {true, true, ""};
}

void restrict_unix_socket(const std::string& address) {
  const std::string path = unix_socket_path(address);
  if (path.empty()) return;
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::runtime_error("cannot read the permissions of unix socket '" + path + "'");
  if ((st.st_mode & S_IRWXO) == 0) return;
  if (::chmod(path.c_str(), st.st_mode & 0770) != 0) {
    throw std::runtime_error("cannot take the permissions of others away from unix socket '" + path + "'");
  }
}

}  // namespace omniview
