// One WHEP viewer: a GStreamer webrtcbin of its own (ICE, DTLS-SRTP, RTP/RTCP, NACK), fed
// the view's shared H.264 as an RTSP client's media is (a subscriber of the view's video
// group: no encode per viewer), answering the viewer's SDP offer.
//
//   appsrc (access units) ! rtph264pay ! webrtcbin
//
// A PLI or FIR from the viewer reaches the payloader as an upstream force-key-unit event
// and asks the shared encoder for a key frame, at most once a second per viewer (the
// encoder itself makes at most four a second for everyone: VideoStream::kMinKeyInterval).
#pragma once

#include <gst/gst.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "server/pipeline/pipeline.h"
#include "server/webrtc/whep_offer.h"

namespace omniview::webrtc {

struct MediaSettings {
  EncodingKey key;       // the view's H.264 group the viewer joins
  double rate_hz = 0;    // its rate (limits.max_rate_hz, as RTSP's)
  std::string stun_server;  // "stun://host:port", empty: host candidates only
  std::string turn_server;  // "turn://user:password@host:port", empty: none
  int min_udp_port = 0, max_udp_port = 0;  // 0: any
};

class WhepSession {
 public:
  using Clock = std::chrono::steady_clock;

  // Subscribes to `view`, builds the media and answers `offer_sdp` (ICE candidates gathered,
  // so the answer is complete: no trickle needed). Throws PipelineError as Pipeline::subscribe
  // does, std::invalid_argument where webrtcbin refuses the offer, std::runtime_error
  // where it fails otherwise.
  WhepSession(Pipeline& pipeline, std::string view, const std::string& peer, const std::string& offer_sdp, const H264Offer& offer,
              const MediaSettings& settings);
  ~WhepSession();
  WhepSession(const WhepSession&) = delete;
  WhepSession& operator=(const WhepSession&) = delete;

  const std::string& view() const { return view_; }
  const std::string& answer_sdp() const { return answer_; }
  // The RTP clock against capture time: a frame captured at Unix time T (µs) carries the
  // RTP timestamp rtp_offset + 90 * (T - capture_epoch_us) / 1000 (mod 2^32), so a viewer
  // tells each picture's capture time (its latency) from its RTP timestamp.
  uint32_t rtp_offset() const { return rtp_offset_; }
  int64_t capture_epoch_us() const { return capture_epoch_us_; }

  // Empty while the viewer is (or may still become) connected; else why the session is over:
  // ICE failed or closed, disconnected or no receiver report moved on for longer than
  // `disconnected_grace` (check_viewer), never connected within `connect_timeout` of the
  // answer, or the media failed.
  std::string gone(Clock::time_point now, Clock::duration connect_timeout, Clock::duration disconnected_grace) const;
  bool connected() const;
  // Reads the viewer's receiver reports (webrtcbin's stats) for gone(); the sweeper calls
  // it every half second.
  void check_viewer(Clock::time_point now);
  uint64_t frames_sent() const { return frames_sent_; }
  uint64_t key_frames_asked() const { return key_frames_asked_; }

 private:
  void build(const H264Offer& offer, const MediaSettings& settings);
  void negotiate(const std::string& offer_sdp);
  void feed();  // the feed thread
  bool push(const v1::Frame& frame);
  void on_ice_state();
  void on_force_key_unit();

  Pipeline& pipeline_;
  const std::string view_;
  ViewSubscription subscriber_;
  GstElement* media_ = nullptr;
  GstElement* webrtc_ = nullptr;
  GstElement* appsrc_ = nullptr;
  std::string answer_;
  uint32_t rtp_offset_ = 0;
  int64_t capture_epoch_us_ = 0;
  const Clock::time_point created_ = Clock::now();

  mutable std::mutex state_mutex_;
  int ice_state_ = 0;  // GstWebRTCICEConnectionState
  Clock::time_point ice_state_since_ = Clock::now();
  bool ever_connected_ = false;
  int64_t reported_sequence_ = -1;         // the viewer's last receiver report's highest sequence
  Clock::time_point reported_at_{};        // when it last moved
  Clock::time_point last_push_{};          // when a frame last went out
  bool viewer_said_bye_ = false;
  std::string media_error_;

  std::atomic<bool> stop_{false};
  std::atomic<int64_t> last_key_request_ns_{0};
  std::atomic<uint64_t> frames_sent_{0};
  std::atomic<uint64_t> key_frames_asked_{0};
  bool awaiting_key_ = true;  // feed thread: frames until a key frame depend on ones not sent
  std::thread thread_;
};

}  // namespace omniview::webrtc
