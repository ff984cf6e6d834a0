#include "server/auth/refusal_log.h"

namespace omniview {

std::string RefusalLog::peer_host(const std::string& peer) {
  if (peer.rfind("ipv4:", 0) != 0 && peer.rfind("ipv6:", 0) != 0) return peer;
  const auto colon = peer.rfind(':');
  return colon > 4 ? peer.substr(0, colon) : peer;  // ipv6:[::1]:5 -> ipv6:[::1]
}

std::optional<uint64_t> RefusalLog::admit(const std::string& peer, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  if (peers_.size() > 4096) {  // bounded, whatever the number of peers: forget quiet ones
    for (auto it = peers_.begin(); it != peers_.end();) {
      it = now - it->second.start >= window_ ? peers_.erase(it) : std::next(it);
    }
    if (peers_.size() > 4096) peers_.clear();
  }
  auto [it, fresh] = peers_.try_emplace(peer_host(peer));
  Window& w = it->second;
  if (fresh || now - w.start >= window_) {
    w.start = now;
    w.written = 0;
  }
  if (w.written >= burst_) {
    ++w.left_out;
    return std::nullopt;
  }
  ++w.written;
  const uint64_t left_out = w.left_out;
  w.left_out = 0;
  return left_out;
}

}  // namespace omniview
