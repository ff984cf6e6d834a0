// What a protocol (the console's, Foxglove's) sees of one WebSocket client: somewhere to
// send replies in order, and per channel a newest-message-wins slot for frames and clouds.
//
// Every function is thread-safe and returns at once: the pipeline's and the pumps' threads
// never wait on a client's network.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace omniview::web {

// One outgoing WebSocket message: `head` (owned) followed by `body`, which `keep` holds
// alive. A frame's encoded image is sent from the pipeline's shared buffer, never copied.
struct OutMessage {
  bool binary = false;
  std::string head;
  std::shared_ptr<const void> keep;
  std::string_view body;
  size_t size() const { return head.size() + body.size(); }
};

class Connection {
 public:
  virtual ~Connection() = default;
  // Replies and notices, sent in order before any channel message. A client that leaves more
  // than web.max_pending_bytes of them unread is disconnected.
  virtual void send_text(std::string text) = 0;
  // The newest message of `channel`: replaces one of the same channel not yet being sent.
  // `done(true)` runs once it was written, `done(false)` when it was replaced or the client
  // left; both on the connection's I/O thread.
  virtual void send_latest(uint32_t channel, OutMessage message, std::function<void(bool written)> done) = 0;
  // Closes the WebSocket with `code` (RFC 6455: 1000 normal, 1008 policy, 1009 too big,
  // 1011 server error) and `reason` (cut to 123 bytes, the protocol's limit).
  virtual void close(uint16_t code, std::string reason) = 0;
  // Runs `task` on the connection's I/O thread after `delay`, unless the connection has
  // ended by then (timeouts, periodic checks of the protocols).
  virtual void after(std::chrono::milliseconds delay, std::function<void()> task) = 0;
  // "ipv4:127.0.0.1:54321": the client, for logs and GetStatus.
  virtual const std::string& peer() const = 0;
};

// A protocol spoken over one connection; its handlers run on the connection's I/O thread.
class Protocol {
 public:
  virtual ~Protocol() = default;
  virtual void on_open() {}
  virtual void on_message(std::string_view data, bool binary) = 0;
  // The connection ended (either side): stop pumping. Also called before destruction.
  virtual void on_close() = 0;
};

}  // namespace omniview::web
