// Moves one subscription's items (a view's frames, a source's clouds) from the pipeline's
// latest-item slot to one client, on a thread of its own as a gRPC stream has one.
//
// It takes the next item only after the client has written the previous one, so what a
// slow client cannot take stays in the pipeline's slot, where it is replaced and counted
// as dropped exactly as for a gRPC client; the pipeline never waits on it.
// For H.264 this is what keeps a stream decodable: nothing between the slot and the socket
// drops or replaces a frame, so every loss is the Subscriber's, which skips to a key frame.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "server/web/ws/connection.h"

namespace omniview::web {

class Pump {
 public:
  // What take() found: a message to send, nothing yet, or the end of the subscription.
  struct Item {
    enum Kind { kNothing, kMessage, kEnd } kind = kNothing;
    OutMessage message;
    // The last check, right before the message goes to the connection: false drops it (a
    // frame of a view that changed since it was taken). None: always sent.
    std::function<bool()> admit;
  };
  struct Source {
    std::function<Item(std::chrono::milliseconds)> take;  // waits up to the timeout
    std::function<void()> sent;                           // the last message reached the client
    std::function<void()> ended;                          // take() said kEnd (on the pump's thread)
    std::function<void()> interrupt;                      // makes a waiting take() return at once
  };

  Pump(std::weak_ptr<Connection> connection, uint32_t channel, Source source);
  ~Pump();
  Pump(const Pump&) = delete;
  Pump& operator=(const Pump&) = delete;

  // Stops and joins the thread (a take() in progress is interrupted). Idempotent.
  void stop();

 private:
  // Everything the thread uses, owned by it and the Pump together: when the thread itself
  // drops the last reference to the connection, the connection's end destroys this Pump
  // on the thread, which must then find its state still there (it detaches, and exits).
  struct Core {
    std::weak_ptr<Connection> connection;
    uint32_t channel = 0;
    Source source;
    std::mutex mutex;
    std::condition_variable changed;
    bool in_flight = false;
    bool written = false;
    bool stop = false;
  };
  static void run(const std::shared_ptr<Core>& core);
  static void fail(const std::shared_ptr<Core>& core, const std::string& why);  // closes with 1011

  std::shared_ptr<Core> core_ = std::make_shared<Core>();
  std::thread thread_;
};

}  // namespace omniview::web
