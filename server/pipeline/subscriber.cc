#include "server/pipeline/subscriber.h"

#include <algorithm>

namespace omniview {

bool Subscriber::due(std::chrono::steady_clock::time_point now) const {
  std::lock_guard lock(mutex_);
  return !closed_ && now >= next_due_;
}

void Subscriber::offer(SharedFrame frame, std::chrono::steady_clock::time_point now) {
  {
    std::lock_guard lock(mutex_);
    if (closed_ || frame->camera().revision() < min_revision_) return;
    if (slot_) ++dropped_;  // the client has not taken the previous one: it is stale now
    slot_ = std::move(frame);
    if (max_rate_hz_ > 0) {
      // Schedule from the nominal time, not `now`, so jitter does not lower the rate; but
      // never let a backlog of "due" slots build up after a pause.
      const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(1.0 / max_rate_hz_));
      next_due_ = std::max(next_due_ + period, now + period / 2);
    }
  }
  ready_.notify_one();
}

void Subscriber::set_min_revision(uint64_t revision) {
  std::lock_guard lock(mutex_);
  min_revision_ = std::max(min_revision_, revision);
  if (slot_ && slot_->camera().revision() < min_revision_) slot_.reset();
}

void Subscriber::count_dropped() {
  std::lock_guard lock(mutex_);
  ++dropped_;
}

void Subscriber::close(grpc::StatusCode code, const std::string& reason) {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    closed_ = true;
    close_code_ = code;
    close_reason_ = reason;
  }
  ready_.notify_all();
}

std::optional<SharedFrame> Subscriber::take(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, timeout, [&] { return slot_ || closed_; });
  if (slot_) return std::exchange(slot_, nullptr);
  if (closed_) return SharedFrame{};
  return std::nullopt;
}

grpc::StatusCode Subscriber::close_code() const {
  std::lock_guard lock(mutex_);
  return close_code_;
}

std::string Subscriber::close_reason() const {
  std::lock_guard lock(mutex_);
  return close_reason_;
}

void Subscriber::count_sent() {
  std::lock_guard lock(mutex_);
  ++sent_;
}

uint64_t Subscriber::frames_sent() const {
  std::lock_guard lock(mutex_);
  return sent_;
}

uint64_t Subscriber::frames_dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace omniview
