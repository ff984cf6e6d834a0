#include "server/pipeline/live_view.h"

#include <algorithm>

#include "server/pipeline/rate_average.h"
#include "server/pipeline/video_stream.h"

namespace omniview {

void LiveView::add_subscriber(std::shared_ptr<Subscriber> s) {
  std::lock_guard lock(mutex_);
  if (subscribers_.empty()) watched_since_ = std::chrono::steady_clock::now();
  subscribers_.push_back(std::move(s));
}

std::shared_ptr<VideoStream> LiveView::join_video(const EncodingKey& key) {
  std::lock_guard lock(mutex_);
  std::erase_if(video_, [](const auto& entry) { return entry.second.expired(); });
  if (auto stream = video_[key].lock()) return stream;
  auto stream = std::make_shared<VideoStream>(key);
  video_[key] = stream;
  return stream;
}

std::chrono::steady_clock::time_point LiveView::watched_since() const {
  std::lock_guard lock(mutex_);
  return watched_since_;
}

void LiveView::remove_subscriber(const Subscriber* s) {
  std::vector<std::shared_ptr<Subscriber>> removed;
  {
    std::lock_guard lock(mutex_);
    for (auto it = subscribers_.begin(); it != subscribers_.end();) {
      if (it->get() == s) {
        removed.push_back(std::move(*it));
        it = subscribers_.erase(it);
      } else {
        ++it;
      }
    }
  }
  // Encodes in flight may still hold it: closed, it refuses their frames.
  for (const auto& r : removed) r->close(ErrorKind::kCancelled, "left the stream");
}

std::vector<std::shared_ptr<Subscriber>> LiveView::subscribers() const {
  std::lock_guard lock(mutex_);
  return subscribers_;
}

size_t LiveView::subscriber_count() const {
  std::lock_guard lock(mutex_);
  return subscribers_.size();
}

void LiveView::close_all(ErrorKind code, const std::string& reason) {
  for (const auto& s : subscribers()) s->close(code, reason);
}

CameraGains LiveView::update_gains(const FusionMap& map, const std::vector<cv::Mat>& images, int channels) {
  std::lock_guard lock(gains_mutex_);
  return gains_.update(map, images, channels);
}

void LiveView::record_map_build(double ms) {
  std::lock_guard lock(mutex_);
  ++stats_.map_rebuilds;
  stats_.last_map_build_ms = ms;
}

void LiveView::record_depth_update() {
  std::lock_guard lock(mutex_);
  ++stats_.depth_updates;
}

void LiveView::record_frame(double latency_ms, std::chrono::steady_clock::time_point now) {
  std::lock_guard lock(mutex_);
  ++stats_.frames;
  stats_.last_latency_ms = latency_ms;
  const double dt = std::chrono::duration<double>(now - stats_.last_frame).count();
  // A pause (nobody watched since the last frame, or an interval far beyond the average:
  // a source that stalled) starts the average again instead of entering it.
  const bool pause = stats_.run_frames == 0 || stats_.last_frame < watched_since_ ||
                     (stats_.mean_interval_s > 0 && dt > std::max(1.0, 4 * stats_.mean_interval_s));
  if (pause) {
    stats_.mean_interval_s = 0;
    stats_.fps = 0;
    stats_.run_frames = 1;
  } else {
    stats_.fps = add_interval(stats_.mean_interval_s, dt, 0.1);
    ++stats_.run_frames;
  }
  stats_.last_frame = now;
}

ViewStats LiveView::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

ViewOverlay& LiveView::overlay(const std::shared_ptr<const RobotModelSetup>& setup) {
  std::lock_guard lock(mutex_);
  if (!overlay_) overlay_ = std::make_unique<ViewOverlay>(setup);
  return *overlay_;
}

}  // namespace omniview
