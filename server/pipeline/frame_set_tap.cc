#include "server/pipeline/frame_set_tap.h"

#include <utility>

namespace omniview {

size_t frame_set_bytes(const FrameSet& frames) {
  size_t bytes = 0;
  for (const cv::Mat& image : frames.images) bytes += image.total() * image.elemSize();
  for (const EncodedImage& e : frames.encoded) bytes += e.bytes ? e.bytes->size() : 0;
  return bytes;
}

void FrameSetTap::offer(std::shared_ptr<const FrameSet> frames) {
  const size_t bytes = frame_set_bytes(*frames);
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    // Skip the newcomer rather than the oldest: what is queued stays one unbroken run, and
    // the gap is where the client was away. One frame set always fits, however large.
    const bool full = queue_.size() >= limits_.max_frame_sets ||
                      (!queue_.empty() && queued_bytes_ + bytes > limits_.max_bytes);
    if (full) {
      ++skipped_;
      return;
    }
    queue_.push_back({{std::move(frames), skipped_}, bytes});
    queued_bytes_ += bytes;
  }
  ready_.notify_one();
}

void FrameSetTap::close(const std::string& reason) {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    closed_ = true;
    reason_ = reason;
    queue_.clear();  // nobody will take them: free the memory now
    queued_bytes_ = 0;
  }
  ready_.notify_all();
}

std::optional<TappedFrameSet> FrameSetTap::take(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, timeout, [&] { return !queue_.empty() || closed_; });
  if (closed_) return TappedFrameSet{};
  if (queue_.empty()) return std::nullopt;
  Entry entry = std::move(queue_.front());
  queue_.pop_front();
  queued_bytes_ -= entry.bytes;
  return std::move(entry.tapped);
}

std::string FrameSetTap::close_reason() const {
  std::lock_guard lock(mutex_);
  return reason_;
}

uint64_t FrameSetTap::skipped() const {
  std::lock_guard lock(mutex_);
  return skipped_;
}

}  // namespace omniview
