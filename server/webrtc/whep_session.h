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
#include <utility>

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
  // How long ICE may take to gather the daemon's candidates before the answer goes out with
  // those it has (host candidates take milliseconds; a STUN server's reflexive one a round
  // trip, a TURN server's relayed one two).
  static constexpr auto kGatherTimeout = std::chrono::seconds(3);

  // Subscribes to `view`, builds the media and answers `offer_sdp` (ICE candidates gathered,
  // so the answer is complete: no trickle needed). Throws PipelineError as Pipeline::subscribe
  // does, std::invalid_argument where webrtcbin refuses the offer, PipelineError
  // kUnavailable where ICE found no candidate (no free port in udp_ports, no interface but
  // loopback), std::runtime_error where it fails otherwise.
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
  // ICE failed or closed, disconnected or no RTCP from the viewer for longer than
  // `disconnected_grace`, never connected within `connect_timeout` of the answer, the viewer
  // said BYE, or the media failed.
  std::string gone(Clock::time_point now, Clock::duration connect_timeout, Clock::duration disconnected_grace) const;
  bool connected() const;
  // A TURN server is configured and gave no relay candidate for the answer (unreachable, or
  // it refused the configured user and password).
  bool relay_missing() const { return relay_missing_; }
  uint64_t frames_sent() const { return frames_sent_; }
  uint64_t key_frames_asked() const { return key_frames_asked_; }

 private:
  void build(const H264Offer& offer, const MediaSettings& settings);
  void negotiate(const std::string& offer_sdp);
  std::string no_candidate_reason() const;  // why ICE gathered nothing, for the 503
  void feed();  // the feed thread
  bool media_ready() const;  // ICE connected and DTLS done: what is pushed reaches the viewer
  void view_went_away();
  bool push(const v1::Frame& frame);
  void on_ice_state();
  void on_force_key_unit();
  void on_viewer_rtcp(bool bye);

  Pipeline& pipeline_;
  const std::string view_;
  ViewSubscription subscriber_;
  GstElement* media_ = nullptr;
  GstElement* webrtc_ = nullptr;
  GstElement* appsrc_ = nullptr;
  GstElement* rtpbin_ = nullptr;  // webrtcbin's: tells when the viewer's RTCP arrives
  std::string answer_;
  std::pair<int, int> settings_ports_{0, 0};  // web.webrtc.udp_ports (0: any)
  bool has_turn_server_ = false;
  bool relay_missing_ = false;
  uint32_t rtp_offset_ = 0;
  int64_t capture_epoch_us_ = 0;
  const Clock::time_point created_ = Clock::now();

  mutable std::mutex state_mutex_;
  int ice_state_ = 0;  // GstWebRTCICEConnectionState
  Clock::time_point ice_state_since_ = Clock::now();
  bool ever_connected_ = false;
  Clock::time_point viewer_rtcp_at_{};     // when the viewer's last RTCP packet arrived
  Clock::time_point last_push_{};          // when a frame last went out
  bool viewer_said_bye_ = false;
  std::string media_error_;

  std::atomic<bool> stop_{false};
  std::atomic<bool> media_started_{false};  // the feed sends (ICE and DTLS were up)
  std::atomic<int64_t> last_key_request_ns_{0};
  std::atomic<uint64_t> frames_sent_{0};
  std::atomic<uint64_t> key_frames_asked_{0};
  bool awaiting_key_ = true;  // feed thread: frames until a key frame depend on ones not sent
  std::thread thread_;
};

}  // namespace omniview::webrtc
