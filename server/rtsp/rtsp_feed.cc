#include "server/rtsp/rtsp_feed.h"

#include <gst/app/gstappsrc.h>
#include <pthread.h>

#include "server/pipeline/video_stream.h"

namespace omniview {
namespace {

// A cached key frame younger than this prerolls a new client's media (older: the next one
// is waited for, at most VideoStream::kMinKeyInterval away once the new client asks).
constexpr auto kCachedKeyFrameAge = std::chrono::seconds(2);

}  // namespace

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
  // Wakes the feed's wait for a frame at once: this runs on the thread that serves every
  // RTSP client, which would otherwise wait out the poll for each client that leaves.
  subscriber_->close(ErrorKind::kCancelled, "the RTSP client left");
  if (thread_.joinable()) thread_.join();
  subscriber_.reset();  // leaves the view's group
  gst_object_unref(appsrc_);
}

void RtspFeed::set_playing(bool playing) {
  if (playing) play_started_ = true;
  playing_ = playing;
}

// The media's preparation (DESCRIBE) waits for the first key frame: its SPS/PPS go into
// the SDP, and the frame waits in the media until PLAY. Frames after it are of no use
// before PLAY (they would pile up in appsrc and go out in one burst). From PLAY on, the
// client gets whole pictures from a fresh key frame on, and a second key frame a little
// later (kMinKeyInterval): a player that probes the stream before it plays, and drops
// what it probed (ffplay -fflags nobuffer), used the first one up in probing, and would
// otherwise show nothing until the periodic key frame 10 s later (issue 29).
bool RtspFeed::wanted(const v1::Frame& frame) {
  if (!prerolled_) {
    prerolled_ = frame.key_frame();
    return prerolled_;
  }
  look_at_play();
  if (!playing_) return false;
  if (awaiting_key_ && !frame.key_frame()) return false;  // it depends on frames the client did not get
  awaiting_key_ = false;
  if (frame.key_frame() && ++keys_since_play_ == 1) ask_key_frame();
  return true;
}

// Feed thread, for every frame and every empty wait: a PLAY since the last look starts the
// wait for a key frame. While it lasts the ask is repeated at the group's key frame pace: a
// key frame asked for may go to the others only (one encoded for a frame rendered before
// this ask, or dropped from a slot this feed was slow to empty), and the client would
// otherwise wait for the periodic one 10 s later.
void RtspFeed::look_at_play() {
  if (!prerolled_) return;
  if (play_started_.exchange(false)) {
    awaiting_key_ = true;
    keys_since_play_ = 0;
    ask_key_frame();
    return;
  }
  if (playing_ && awaiting_key_ && VideoStream::Clock::now() - last_ask_ >= VideoStream::kMinKeyInterval) {
    ask_key_frame();
  }
}

void RtspFeed::ask_key_frame() {
  if (subscriber_->video()) subscriber_->video()->request_key_frame();
  last_ask_ = VideoStream::Clock::now();
}

void RtspFeed::run() {
  GstAppSrc* src = GST_APP_SRC(appsrc_);
  const auto push = [&](const v1::Frame& frame) {
    const std::string& data = frame.data();
    GstBuffer* buffer = gst_buffer_new_memdup(data.data(), data.size());
    if (!frame.key_frame()) GST_BUFFER_FLAG_SET(buffer, GST_BUFFER_FLAG_DELTA_UNIT);
    // Timestamps: appsrc stamps each buffer with the running time it arrives at (live).
    return gst_app_src_push_buffer(src, buffer) == GST_FLOW_OK;
  };
  // The DESCRIBE waiting on the server's thread needs a key frame: the group's newest, if
  // recent, serves at once (the client gets a fresh one from PLAY on anyway).
  if (const auto& video = subscriber_->video()) {
    const auto [cached, made] = video->last_key_frame();
    if (cached && VideoStream::Clock::now() - made < kCachedKeyFrameAge && subscriber_->hand_over(*cached) &&
        wanted(*cached) && !push(*cached)) {
      gst_app_src_end_of_stream(src);
      return;
    }
  }
  while (!stop_) {
    const auto frame = subscriber_->take(std::chrono::milliseconds(100));
    if (!frame) {
      look_at_play();
      continue;
    }
    if (!*frame) break;  // the view was deleted, or the daemon stops
    // The view's revision first (it counts what reaches the client), then what this client
    // can use now (a media that prerolled must not take a frame the revision check drops).
    if (!subscriber_->hand_over(**frame) || !wanted(**frame)) continue;
    if (!push(**frame)) break;  // the media is going away
  }
  gst_app_src_end_of_stream(src);
}

}  // namespace omniview
