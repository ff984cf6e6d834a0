#include "server/rtsp/rtsp_feed.h"

#include <gst/app/gstappsrc.h>
#include <pthread.h>

namespace omniview {

RtspFeed::RtspFeed(Pipeline& pipeline, const std::string& view, const EncodingKey& key, double rate_hz,
                   GstElement* appsrc)
    : pipeline_(pipeline), view_(view), appsrc_(GST_ELEMENT(gst_object_ref(appsrc))) {
  try {
    // Stale frames too: a video client's stream carries them anyway (docs/API.md).
    subscriber_ = pipeline_.subscribe(view_, "rtsp", key, rate_hz, true);
  } catch (...) {
    gst_object_unref(appsrc_);
    throw;
  }
  thread_ = std::thread([this] {
    pthread_setname_np(pthread_self(), "rtsp-feed");
    run();
  });
}

RtspFeed::~RtspFeed() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  pipeline_.unsubscribe(view_, subscriber_.get());
  gst_object_unref(appsrc_);
}

void RtspFeed::run() {
  GstAppSrc* src = GST_APP_SRC(appsrc_);
  while (!stop_) {
    const auto frame = subscriber_->take(std::chrono::milliseconds(100));
    if (!frame) continue;
    if (!*frame) break;  // the view was deleted, or the daemon stops
    if (!subscriber_->hand_over(**frame)) continue;  // the view changed since it was taken
    const std::string& data = (*frame)->data();
    GstBuffer* buffer = gst_buffer_new_memdup(data.data(), data.size());
    if (!(*frame)->key_frame()) GST_BUFFER_FLAG_SET(buffer, GST_BUFFER_FLAG_DELTA_UNIT);
    // Timestamps: appsrc stamps each buffer with the running time it arrives at (live).
    if (gst_app_src_push_buffer(src, buffer) != GST_FLOW_OK) break;  // the media is going away
  }
  gst_app_src_end_of_stream(src);
}

}  // namespace omniview
