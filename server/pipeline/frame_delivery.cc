#include "server/pipeline/frame_delivery.h"

#include <exception>
#include <string>

#include <google/protobuf/util/time_util.h>

#include "server/pipeline/frame_encoder.h"
#include "server/pipeline/video_stream.h"

namespace omniview {

namespace {

using Clock = std::chrono::steady_clock;

google::protobuf::Timestamp to_timestamp(std::chrono::system_clock::time_point t) {
  return google::protobuf::util::TimeUtil::NanosecondsToTimestamp(
      std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count());
}

}  // namespace

void encode_and_offer(LiveView& view, const ViewState& state, RenderedFrame& rendered, const EncodingKey& key,
                      const std::vector<std::shared_ptr<Subscriber>>& subscribers, VideoStream* video) {
  // The view changed while this frame waited for an encoder: its clients refuse it, so it
  // is not encoded (for H.264 this keeps the stream whole: the frame never enters the
  // encoder, so no later frame refers to it).
  if (view.state()->revision > state.revision) {
    for (auto& s : subscribers) s->count_dropped();
    return;
  }
  auto frame = std::make_shared<v1::Frame>();
  try {
    frame->set_view(state.spec.name);
    frame->set_sequence(rendered.sequence);
    *frame->mutable_capture_time() = to_timestamp(rendered.capture_time);
    *frame->mutable_camera() = *state.description;
    frame->set_coverage(state.coverage);
    if (state.depth) frame->set_measured_depth(state.depth->measured_fraction);
    if (rendered.stale) {
      frame->set_stale(true);
      frame->set_stale_reason(rendered.stale_reason);
    }
    if (key.encoding == v1::H264) {
      if (video == nullptr) throw std::logic_error("an H.264 frame without its group's encoder");
      // The view's rate once it has averaged a few intervals since its last pause; a view
      // just watched again has not (the stream then measures its own).
      const ViewStats stats = view.stats();
      auto au = video->encode(rendered.image, rendered.arrival,
                              stats.run_frames > VideoStream::kRateIntervals ? stats.fps : 0, state.revision,
                              rendered.source_rate_hz);
      if (au.data.empty()) return;  // a new stream's first frames: they only measured the rate
      frame->set_encoding(v1::H264);
      frame->set_width(rendered.image.cols);
      frame->set_height(rendered.image.rows);
      frame->set_channels(key.gray || rendered.image.channels() == 1 ? 1 : 3);
      frame->set_key_frame(au.key_frame);
      frame->set_data(std::move(au.data));
    } else {
      encode_frame(rendered.image, key, *frame);
    }
  } catch (const std::invalid_argument& e) {
    // The view changed into something this encoding cannot carry (H.264 beyond its largest size).
    for (auto& s : subscribers) {
      s->close(ErrorKind::kFailedPrecondition, "view '" + state.spec.name + "': " + e.what());
    }
    return;
  } catch (const std::exception& e) {
    for (auto& s : subscribers) s->close(ErrorKind::kInternal, std::string("cannot encode frames: ") + e.what());
    return;
  }
  const auto offered = Clock::now();
  const double latency_ms = std::chrono::duration<double, std::milli>(offered - rendered.arrival).count();
  frame->set_latency_ms(latency_ms);
  SharedFrame shared = std::move(frame);
  if (video != nullptr && shared->key_frame()) video->keep_key_frame(shared);
  for (auto& s : subscribers) s->offer(shared, offered);
  if (!rendered.stale && !rendered.counted.exchange(true)) view.record_frame(latency_ms, offered);
}

}  // namespace omniview
