// One rendered view image on its way to clients: encoded per EncodingKey (on an encoder
// thread, see encoder_pool.h) and offered to that key's subscribers.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "server/pipeline/live_view.h"
#include "server/pipeline/subscriber.h"

namespace omniview {

struct RenderedFrame {
  cv::Mat image;  // never written after rendering: shared by every encoding of it
  uint64_t sequence = 0;
  std::chrono::system_clock::time_point capture_time;
  std::chrono::steady_clock::time_point arrival;  // of the source's frame set
  double source_rate_hz = 0;  // the source's nominal rate (Source::nominal_rate_hz), 0: unknown
  std::atomic<bool> counted{false};  // the view's statistics count the first encoding delivered
  // Rendered again from the source's last images because it delivers nothing new
  // (staleness.h): sent marked, and not counted as a new frame.
  bool stale = false;
  std::string stale_reason;
};

// Encodes `rendered` in `key` (H264: through `video`, the group's shared encoder), offers
// it to `subscribers` (a failed encoding ends their streams: FAILED_PRECONDITION for a view
// the encoding cannot take, such as H.264 of an odd size, INTERNAL otherwise) and records
// the frame in `view`'s statistics. A frame of a revision older than the view's current one
// is not encoded (counted as dropped). Never throws.
void encode_and_offer(LiveView& view, const ViewState& state, RenderedFrame& rendered, const EncodingKey& key,
                      const std::vector<std::shared_ptr<Subscriber>>& subscribers, VideoStream* video = nullptr);

}  // namespace omniview
