#include "server/web/foxglove/foxglove_sources.h"

#include <chrono>
#include <condition_variable>
#include <mutex>

#include "server/web/foxglove/foxglove_messages.h"

namespace omniview::web::foxglove_io {

namespace {

constexpr auto kTransformPeriod = std::chrono::seconds(1);

// The /tf channel's clock: a FrameTransforms message now, then once a period; interrupt()
// ends a wait at once.
class Ticker {
 public:
  bool wait(std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    if (now >= next_) {
      next_ = now + kTransformPeriod;
      return true;
    }
    changed_.wait_for(lock, std::min<std::chrono::steady_clock::duration>(timeout, next_ - now),
                      [&] { return stopped_; });
    return false;
  }
  bool stopped() {
    std::lock_guard lock(mutex_);
    return stopped_;
  }
  void interrupt() {
    {
      std::lock_guard lock(mutex_);
      stopped_ = true;
    }
    changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::chrono::steady_clock::time_point next_{};
  bool stopped_ = false;
};

}  // namespace

std::function<OutMessage(const SharedFrame&)> frame_data(uint32_t subscription, Topic topic, std::string frame_id) {
  return [subscription, topic, frame_id = std::move(frame_id)](const SharedFrame& frame) {
    const uint64_t time = time_ns(frame->capture_time());
    switch (topic) {
      case Topic::kImage:
        return message_data(subscription, time, compressed_image_prefix(*frame, frame_id), 2, frame->data(), frame);
      case Topic::kVideo:
        return message_data(subscription, time, compressed_video_prefix(*frame, frame_id), 3, frame->data(), frame);
      default:
        return message_data(subscription, time, camera_calibration(*frame, frame_id), 0, {}, nullptr);
    }
  };
}

OutMessage cloud_data(uint32_t subscription, const SharedCloud& cloud) {
  // A copy with the alpha byte appended to each point (point_cloud_prefix): a few hundred kB
  // at most 10 Hz, made on this subscription's pump thread, not the pipeline's.
  auto points = std::make_shared<const std::string>(foxglove_points(*cloud));
  const std::string_view data = *points;
  return message_data(subscription, time_ns(cloud->stamp()), point_cloud_prefix(*cloud), 6, data, std::move(points));
}

Pump::Source transforms_source(uint32_t subscription, Pipeline& pipeline) {
  auto ticker = std::make_shared<Ticker>();
  Pump::Source source;
  source.take = [ticker, subscription, &pipeline](std::chrono::milliseconds timeout) {
    Pump::Item item;
    if (ticker->stopped()) {
      item.kind = Pump::Item::kEnd;
      return item;
    }
    if (!ticker->wait(timeout)) return item;
    item.kind = Pump::Item::kMessage;
    const auto now =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch());
    item.message = message_data(subscription, static_cast<uint64_t>(now.count()), frame_transforms(pipeline), 0, {},
                                nullptr);
    return item;
  };
  source.interrupt = [ticker] { ticker->interrupt(); };
  return source;
}

}  // namespace omniview::web::foxglove_io
