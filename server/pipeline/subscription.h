// A front end's hold on one stream out of the pipeline (a view's frames, a source's clouds
// or frame sets): the subscriber while it lives, and leaving the pipeline when it ends,
// however it ends (client gone, view deleted, shutdown, an exception). Every front end
// holds its streams this way (gRPC, the WebSockets, RTSP, WHEP, the black box), so none
// can forget to leave or leave twice.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <utility>

namespace omniview {

// How often a front end's wait for the next item wakes to see whether its client left.
inline constexpr auto kFrontEndPoll = std::chrono::milliseconds(100);

template <class S>
class Subscription {
 public:
  Subscription() = default;
  Subscription(std::shared_ptr<S> subscriber, std::function<void(const S*)> leave)
      : subscriber_(std::move(subscriber)), leave_(std::move(leave)) {}
  ~Subscription() { reset(); }
  Subscription(Subscription&& other) noexcept { *this = std::move(other); }
  Subscription& operator=(Subscription&& other) noexcept {
    if (this != &other) {
      reset();
      subscriber_ = std::move(other.subscriber_);
      leave_ = std::move(other.leave_);
      other.subscriber_.reset();
    }
    return *this;
  }
  Subscription(const Subscription&) = delete;
  Subscription& operator=(const Subscription&) = delete;

  // Leaves the pipeline now (idempotent). The subscriber object stays valid for whoever
  // still holds it (a pump finishing its last item): it just gets nothing more.
  void reset() noexcept {
    if (!subscriber_) return;
    try {
      leave_(subscriber_.get());
    } catch (...) {
      // The pipeline stopping meanwhile: there is nothing left to leave.
    }
    subscriber_.reset();
  }

  S* operator->() const { return subscriber_.get(); }
  S& operator*() const { return *subscriber_; }
  const std::shared_ptr<S>& shared() const { return subscriber_; }
  explicit operator bool() const { return subscriber_ != nullptr; }

 private:
  std::shared_ptr<S> subscriber_;
  std::function<void(const S*)> leave_;
};

class Subscriber;
class CloudSubscriber;
class FrameSetTap;
using ViewSubscription = Subscription<Subscriber>;
using CloudSubscription = Subscription<CloudSubscriber>;
using TapSubscription = Subscription<FrameSetTap>;

}  // namespace omniview
