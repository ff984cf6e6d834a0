// A source and the pipeline's side of it: a latest-frame-set slot filled by the source's
// thread and drained by one render worker, plus the source's statistics.
//
// If frame sets come faster than the worker renders them the slot keeps only the newest
// (the skipped ones are counted as dropped): an operator wants the present, not a queue.
// Recordings are the exception: each has its own bounded queue (frame_set_tap.h).
#pragma once

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "server/pipeline/frame_set_tap.h"
#include "server/source/source.h"

namespace omniview {

struct SourceStats {
  uint64_t frames = 0;    // frame sets received
  uint64_t dropped = 0;   // replaced in the slot before the worker took them
  double rate_hz = 0;     // 1 / the exponentially averaged interval
  double mean_interval_s = 0;
  std::chrono::steady_clock::time_point last_arrival{};
};

class SourceChannel {
 public:
  explicit SourceChannel(std::unique_ptr<Source> source) : source_(std::move(source)) {}

  Source& source() { return *source_; }
  const Source& source() const { return *source_; }

  // Source thread: store the newest frame set and wake the worker. Never blocks for long.
  void deliver(std::shared_ptr<const FrameSet> frames);
  // Worker thread: the next frame set; null once closed, or when none came within
  // `timeout` (the worker then checks whether its views have gone stale).
  std::shared_ptr<const FrameSet> next(std::chrono::milliseconds timeout);
  void close();
  bool closed() const;

  // The newest frame set seen (for snapshots of rig and images), may be null.
  std::shared_ptr<const FrameSet> latest() const;

  // A passive tap (the black box) takes what flows and asks the source for nothing: it is
  // not counted by tap_count(), which makes a source deliver every camera.
  void add_tap(std::shared_ptr<FrameSetTap> tap, bool passive = false);
  void remove_tap(const FrameSetTap* tap);
  size_t tap_count() const;
  void close_taps(const std::string& reason);

  SourceStats stats() const;

  // The rig the cloud path last told the source its wanted cameras for (worker thread only).
  const std::shared_ptr<const Rig>& cloud_rig_seen() const { return cloud_rig_seen_; }
  void set_cloud_rig_seen(std::shared_ptr<const Rig> rig) { cloud_rig_seen_ = std::move(rig); }

 private:
  std::shared_ptr<const Rig> cloud_rig_seen_;
  std::unique_ptr<Source> source_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::shared_ptr<const FrameSet> pending_;
  std::shared_ptr<const FrameSet> latest_;
  bool closed_ = false;
  std::vector<std::shared_ptr<FrameSetTap>> taps_;
  std::vector<std::shared_ptr<FrameSetTap>> passive_taps_;
  SourceStats stats_;
};

}  // namespace omniview
