#include "server/pipeline/source_channel.h"

#include <algorithm>

#include "server/pipeline/rate_average.h"

namespace omniview {

void SourceChannel::deliver(std::shared_ptr<const FrameSet> frames) {
  std::vector<std::shared_ptr<FrameSetTap>> taps;
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    const auto now = frames->arrival;
    if (stats_.last_arrival.time_since_epoch().count() != 0) {
      const double dt = std::chrono::duration<double>(now - stats_.last_arrival).count();
      stats_.rate_hz = add_interval(stats_.mean_interval_s, dt, 0.2);
    }
    stats_.last_arrival = now;
    ++stats_.frames;
    if (pending_) ++stats_.dropped;
    pending_ = frames;
    latest_ = frames;
    taps = taps_;
    taps.insert(taps.end(), passive_taps_.begin(), passive_taps_.end());
  }
  ready_.notify_one();
  for (const auto& t : taps) t->offer(frames);
}

std::shared_ptr<const FrameSet> SourceChannel::next(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, timeout, [&] { return pending_ || closed_; });
  if (closed_) return nullptr;
  return std::exchange(pending_, nullptr);
}

bool SourceChannel::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

void SourceChannel::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
}

std::shared_ptr<const FrameSet> SourceChannel::latest() const {
  std::lock_guard lock(mutex_);
  return latest_;
}

void SourceChannel::add_tap(std::shared_ptr<FrameSetTap> tap, bool passive) {
  std::lock_guard lock(mutex_);
  (passive ? passive_taps_ : taps_).push_back(std::move(tap));
}

void SourceChannel::remove_tap(const FrameSetTap* tap) {
  std::lock_guard lock(mutex_);
  std::erase_if(taps_, [&](const auto& p) { return p.get() == tap; });
  std::erase_if(passive_taps_, [&](const auto& p) { return p.get() == tap; });
}

size_t SourceChannel::tap_count() const {
  std::lock_guard lock(mutex_);
  return taps_.size();
}

void SourceChannel::close_taps(const std::string& reason) {
  std::vector<std::shared_ptr<FrameSetTap>> taps;
  {
    std::lock_guard lock(mutex_);
    taps = taps_;
    taps.insert(taps.end(), passive_taps_.begin(), passive_taps_.end());
  }
  for (const auto& t : taps) t->close(reason);
}

SourceStats SourceChannel::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace omniview
