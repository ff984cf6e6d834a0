// One subscription as a web protocol holds it: the Pump that carries its items to the
// client and its way out of the pipeline. Both protocols (console, Foxglove) start their
// view and cloud subscriptions through here.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>

#include "server/pipeline/errors.h"
#include "server/pipeline/subscription.h"

#include "server/web/stream/pump.h"

namespace omniview::web {

// A Pump::Source over a pipeline subscriber: a view's Subscriber or a CloudSubscriber, which
// share take() and close(). A frame passes its Subscriber's hand_over() right before it
// goes to the connection (which counts it sent); a cloud is counted once written.
// `to_message` makes each item's message; `ended` runs when the subscriber closed on its
// own (Stream drops it after stop()).
template <class AnySubscriber, class ToMessage>
Pump::Source subscriber_source(std::shared_ptr<AnySubscriber> subscriber, ToMessage to_message,
                               std::function<void(const AnySubscriber&)> ended) {
  Pump::Source source;
  source.take = [subscriber, to_message = std::move(to_message)](std::chrono::milliseconds timeout) {
    Pump::Item item;
    const auto next = subscriber->take(timeout);  // nullopt: nothing yet; a null item: closed
    if (!next) return item;
    item.kind = *next ? Pump::Item::kMessage : Pump::Item::kEnd;
    if (*next) {
      item.message = to_message(*next);
      if constexpr (requires { subscriber->hand_over(**next); }) {
        item.admit = [subscriber, frame = *next] { return subscriber->hand_over(*frame); };
      }
    }
    return item;
  };
  if constexpr (requires { subscriber->count_sent(); }) source.sent = [subscriber] { subscriber->count_sent(); };
  source.ended = [subscriber, ended = std::move(ended)] { ended(*subscriber); };
  source.interrupt = [subscriber] { subscriber->close(ErrorKind::kCancelled, "unsubscribed"); };
  return source;
}

// A Stream's `release` that ends `subscription` (leaves the pipeline) at stop().
template <class S>
std::function<void()> release_of(Subscription<S> subscription) {
  auto held = std::make_shared<Subscription<S>>(std::move(subscription));
  return [held] { held->reset(); };
}

class Stream {
 public:
  // Starts pumping `source` to `channel` of the connection. `release` leaves the pipeline
  // (release_of the subscription); it runs once, at stop().
  Stream(std::weak_ptr<Connection> connection, uint32_t channel, Pump::Source source, std::function<void()> release);
  ~Stream();
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;

  // Ends the stream at the client's wish: the source's `ended` notice stays silent, the
  // pump's thread is joined and the pipeline released. Idempotent.
  void stop();

 private:
  std::shared_ptr<std::atomic<bool>> stopping_ = std::make_shared<std::atomic<bool>>(false);
  std::function<void()> release_;
  std::unique_ptr<Pump> pump_;
};

}  // namespace omniview::web
