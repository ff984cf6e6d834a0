// A bound UDP socket that a thread reads datagrams from, waking every so often to notice a
// stop. Bound at construction, so a port in use is a config error at start-up, not a
// silence later.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace omniview {

class UdpListener {
 public:
  // Binds `address` (numeric IPv4/IPv6 or a host name) and `port` (0: a free one). Throws
  // std::runtime_error saying why (address not of this machine, port in use).
  UdpListener(const std::string& address, int port);
  ~UdpListener();
  UdpListener(const UdpListener&) = delete;
  UdpListener& operator=(const UdpListener&) = delete;

  int port() const { return port_; }

  // Waits up to `timeout` for one datagram; true with its bytes in `data` and the sender's
  // numeric address in `sender`, false when none came.
  bool receive(std::vector<uint8_t>& data, std::string& sender, std::chrono::milliseconds timeout);

 private:
  int fd_ = -1;
  int port_ = 0;
};

}  // namespace omniview
