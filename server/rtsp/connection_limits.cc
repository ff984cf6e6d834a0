#include "server/rtsp/connection_limits.h"

namespace omniview {

std::unique_ptr<ConnectionLimits::Slot> ConnectionLimits::acquire(const std::string& host, std::string* why) {
  std::lock_guard lock(mutex_);
  if (open_ >= max_connections_) {
    if (why) *why = std::to_string(open_) + " connections open (rtsp.max_connections)";
    return nullptr;
  }
  int& from_host = per_host_[host];
  if (from_host >= max_per_client_) {
    if (why) *why = std::to_string(from_host) + " connections open from it (rtsp.max_connections_per_client)";
    return nullptr;
  }
  ++from_host;
  ++open_;
  return std::make_unique<Slot>(shared_from_this(), host);
}

int ConnectionLimits::open() const {
  std::lock_guard lock(mutex_);
  return open_;
}

void ConnectionLimits::release(const std::string& host) {
  std::lock_guard lock(mutex_);
  --open_;
  const auto it = per_host_.find(host);
  if (it != per_host_.end() && --it->second <= 0) per_host_.erase(it);
}

}  // namespace omniview
