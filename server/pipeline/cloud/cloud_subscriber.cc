#include "server/pipeline/cloud/cloud_subscriber.h"

#include <algorithm>

namespace omniview {

bool CloudSubscriber::due(std::chrono::steady_clock::time_point now) const {
  std::lock_guard lock(mutex_);
  return !closed_ && now >= next_due_;
}

void CloudSubscriber::offer(SharedCloud cloud, std::chrono::steady_clock::time_point now) {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    if (slot_) ++dropped_;  // not taken yet: stale now
    slot_ = std::move(cloud);
    if (max_rate_hz_ > 0) {
      // From the nominal time so jitter does not lower the rate, without a backlog after a pause.
      const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(1.0 / max_rate_hz_));
      next_due_ = std::max(next_due_ + period, now + period / 2);
    }
  }
  ready_.notify_one();
}

void CloudSubscriber::close(ErrorKind code, const std::string& reason) {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    closed_ = true;
    close_kind_ = code;
    close_reason_ = reason;
  }
  ready_.notify_all();
}

std::optional<SharedCloud> CloudSubscriber::take(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, timeout, [&] { return slot_ || closed_; });
  if (slot_) return std::exchange(slot_, nullptr);
  if (closed_) return SharedCloud{};
  return std::nullopt;
}

ErrorKind CloudSubscriber::close_kind() const {
  std::lock_guard lock(mutex_);
  return close_kind_;
}

std::string CloudSubscriber::close_reason() const {
  std::lock_guard lock(mutex_);
  return close_reason_;
}

void CloudSubscriber::count_sent() {
  std::lock_guard lock(mutex_);
  ++sent_;
}

uint64_t CloudSubscriber::clouds_sent() const {
  std::lock_guard lock(mutex_);
  return sent_;
}

uint64_t CloudSubscriber::clouds_dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace omniview
