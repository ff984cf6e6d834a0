#include "cli/client/display_probe.h"

#include <netdb.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstring>

namespace omniview::cli {
namespace {

// Connects `fd` to `address`, giving up after a second; true on success.
bool connect_within_a_second(int fd, const sockaddr* address, socklen_t length) {
  timeval timeout{1, 0};
  setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);  // Linux bounds connect() by it
  const bool ok = connect(fd, address, length) == 0;
  close(fd);
  return ok;
}

bool unix_socket_answers(const std::string& path, bool abstract) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.size() + 2 > sizeof address.sun_path) return false;
  std::memcpy(address.sun_path + (abstract ? 1 : 0), path.data(), path.size());
  const socklen_t length = offsetof(sockaddr_un, sun_path) + (abstract ? 1 : 0) + path.size() + (abstract ? 0 : 1);
  const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  return fd >= 0 && connect_within_a_second(fd, reinterpret_cast<const sockaddr*>(&address), length);
}

bool tcp_answers(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* results = nullptr;
  if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &results) != 0) return false;
  bool ok = false;
  for (const addrinfo* r = results; r && !ok; r = r->ai_next) {
    const int fd = socket(r->ai_family, r->ai_socktype, r->ai_protocol);
    ok = fd >= 0 && connect_within_a_second(fd, r->ai_addr, r->ai_addrlen);
  }
  freeaddrinfo(results);
  return ok;
}

}  // namespace

std::string probe_x_display(const std::string& display) {
  const size_t colon = display.rfind(':');
  if (colon == std::string::npos) return "DISPLAY '" + display + "' names no display number";
  const std::string host = display.substr(0, colon);
  std::string number = display.substr(colon + 1);
  number = number.substr(0, number.find('.'));
  if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos || number.size() > 5) {
    return "DISPLAY '" + display + "' names no display number";
  }
  if (host.empty() || host == "unix") {
    const std::string path = "/tmp/.X11-unix/X" + number;
    if (unix_socket_answers(path, false) || unix_socket_answers(path, true)) return "";
    return "DISPLAY '" + display + "': nothing listens on " + path;
  }
  const int port = 6000 + std::stoi(number);
  if (tcp_answers(host, port)) return "";
  return "DISPLAY '" + display + "': nothing answers on " + host + ":" + std::to_string(port) +
         " (an ssh -X forwarding that has ended?)";
}

}  // namespace omniview::cli
