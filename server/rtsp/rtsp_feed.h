// One RTSP client's media fed from the pipeline: a subscriber of the view's H264 group
// whose access units are pushed into the media's appsrc, on a thread of its own.
#pragma once

#include <gst/gst.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include "server/pipeline/pipeline.h"

namespace omniview {

class RtspFeed {
 public:
  // Subscribes at once (the group's encoder makes a key frame for it) and starts pushing.
  // Throws PipelineError as Pipeline::subscribe does (a view deleted meanwhile).
  RtspFeed(Pipeline& pipeline, const std::string& view, const EncodingKey& key, double rate_hz, GstElement* appsrc);
  // Stops pushing and leaves the group (the last one out frees its encoder).
  ~RtspFeed();
  RtspFeed(const RtspFeed&) = delete;
  RtspFeed& operator=(const RtspFeed&) = delete;

  // Server thread: the client's PLAY (true) or PAUSE (false) was answered.
  void set_playing(bool playing);

 private:
  void run();
  // Feed thread: whether `frame` goes to the client now (see run()).
  bool wanted(const v1::Frame& frame);
  void look_at_play();
  void ask_key_frame();

  Pipeline& pipeline_;
  const std::string view_;
  ViewSubscription subscriber_;
  GstElement* appsrc_;  // a reference of our own
  std::atomic<bool> stop_{false};
  std::atomic<bool> playing_{false};
  std::atomic<bool> play_started_{false};  // a PLAY since the feed thread last looked
  // Feed thread only.
  bool prerolled_ = false;  // the first key frame went out: the media knows its SPS/PPS
  bool awaiting_key_ = false;  // frames until the next key frame depend on ones not sent
  int keys_since_play_ = 0;
  std::chrono::steady_clock::time_point last_ask_{};  // of a key frame, for this client
  std::thread thread_;
};

}  // namespace omniview
