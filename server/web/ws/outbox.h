// The queue between a client's protocol and its socket: replies first, in order; then the
// channels' newest messages, one channel after another so a large cloud never starves a
// view. Single-threaded: the WebSocket session uses it on its I/O thread only.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>

#include "server/web/ws/connection.h"

namespace omniview::web {

class Outbox {
 public:
  explicit Outbox(size_t max_pending_text_bytes) : max_text_bytes_(max_pending_text_bytes) {}

  // False when the client already has more replies unread than allowed: drop it.
  bool push_text(std::string text);
  void push_latest(uint32_t channel, OutMessage message, std::function<void(bool)> done);

  // The next message to write, or nullopt when there is none. Its `done` (if any) is
  // returned with it, to run once written.
  struct Next {
    OutMessage message;
    std::function<void(bool)> done;
  };
  std::optional<Next> pop();
  // The client left: every waiting message's `done(false)`.
  void drop_all();
  // Closing: channel messages are dropped (`done(false)`), replies still go out.
  void drop_channels();
  bool empty() const { return texts_.empty() && latest_.empty(); }

 private:
  const size_t max_text_bytes_;
  std::deque<std::string> texts_;
  size_t text_bytes_ = 0;
  std::map<uint32_t, Next> latest_;
  uint32_t last_channel_ = 0;  // round robin: the channel after this one goes next
};

}  // namespace omniview::web
