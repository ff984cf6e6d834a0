// A client recording what a source delivers (StreamSourceFrames): a bounded queue of frame
// sets between the source's thread and the client's RPC thread.
//
// Unlike a view's latest-frame slot, a recording wants every frame set, so a client that
// is slow for a moment (a disk flush) gets them all later. The queue is bounded in frame
// sets and in bytes, so memory stays bounded whatever the client does; a frame set that
// does not fit is skipped and counted, and each queued one carries how many were skipped
// before it, so the client can say honestly what its recording lacks. The source's thread
// never waits on it.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "server/source/frame_set.h"

namespace omniview {

struct TapLimits {
  size_t max_frame_sets = 32;             // ~2 s of a 15 Hz robot
  size_t max_bytes = size_t{256} << 20;   // decoded pixels and encoded bytes held
};

// One frame set as the client takes it.
struct TappedFrameSet {
  std::shared_ptr<const FrameSet> frames;  // null once the tap is closed
  uint64_t skipped_before = 0;  // frame sets skipped (queue full) since the tap opened, before this one
};

class FrameSetTap {
 public:
  explicit FrameSetTap(TapLimits limits = {}) : limits_(limits) {}

  // Source thread: queues `frames`, or skips it (and counts) if the queue is full.
  void offer(std::shared_ptr<const FrameSet> frames);
  void close(const std::string& reason);
  // Client thread: the oldest queued frame set; nullopt on timeout. Once closed, a null
  // `frames` (what is still queued is not delivered: the stream ends).
  std::optional<TappedFrameSet> take(std::chrono::milliseconds timeout);
  std::string close_reason() const;
  uint64_t skipped() const;
  const TapLimits& limits() const { return limits_; }

 private:
  struct Entry {
    TappedFrameSet tapped;
    size_t bytes = 0;
  };

  const TapLimits limits_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Entry> queue_;
  size_t queued_bytes_ = 0;
  bool closed_ = false;
  std::string reason_;
  uint64_t skipped_ = 0;
};

// What a frame set holds in memory: its images' pixels plus any encoded bytes. Images
// shared with other frame sets are counted each time (an over-estimate, on the safe side).
size_t frame_set_bytes(const FrameSet& frames);

}  // namespace omniview
