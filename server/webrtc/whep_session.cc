#include "server/webrtc/whep_session.h"

#define GST_USE_UNSTABLE_API  // webrtcbin's library (stable in practice since 1.16; says so from 1.24)
#include <gst/app/gstappsrc.h>
#include <gst/sdp/sdp.h>
#include <gst/webrtc/webrtc.h>
#include <ifaddrs.h>
#include <net/if.h>
#include <pthread.h>

#include <random>

#include "server/pipeline/video_stream.h"

namespace omniview::webrtc {
namespace {

// A viewer's PLI/FIR asks the shared encoder for a key frame at most this often, so one bad
// link cannot turn everyone's stream into key frames.
constexpr auto kKeyRequestInterval = std::chrono::seconds(1);
// Unsent bytes in the media past which frames are skipped until the next key frame (a link
// slower than the stream: better a skip than seconds of delay).
constexpr guint64 kMaxQueuedBytes = 4 << 20;

int64_t unix_us_now() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

int64_t capture_us(const v1::Frame& frame) {
  return frame.capture_time().seconds() * 1000000 + frame.capture_time().nanos() / 1000;
}

std::string error_of(const GstStructure* reply, const char* what) {
  if (reply == nullptr) return "";  // done, nothing to say
  GError* e = nullptr;
  if (gst_structure_has_field(reply, "error")) gst_structure_get(reply, "error", G_TYPE_ERROR, &e, nullptr);
  std::string message = e ? e->message : "";
  if (e) g_error_free(e);
  return message.empty() ? "" : std::string(what) + ": " + message;
}

// Emits `signal` with `description` (may be null) and waits for its promise's reply; throws
// std::invalid_argument with webrtcbin's reason where it refused.
GstWebRTCSessionDescription* negotiate_step(GstElement* webrtc, const char* signal,
                                            GstWebRTCSessionDescription* description, const char* answer_field) {
  GstPromise* promise = gst_promise_new();
  if (description) {
    g_signal_emit_by_name(webrtc, signal, description, promise);
  } else {
    g_signal_emit_by_name(webrtc, signal, nullptr, promise);
  }
  const GstPromiseResult result = gst_promise_wait(promise);
  const GstStructure* reply = gst_promise_get_reply(promise);
  std::string error = result == GST_PROMISE_RESULT_REPLIED ? error_of(reply, signal) : std::string(signal) + ": no reply";
  GstWebRTCSessionDescription* answer = nullptr;
  if (error.empty() && answer_field) {
    gst_structure_get(reply, answer_field, GST_TYPE_WEBRTC_SESSION_DESCRIPTION, &answer, nullptr);
    if (answer == nullptr) error = std::string(signal) + ": webrtcbin made no answer";
  }
  gst_promise_unref(promise);
  if (!error.empty()) throw std::invalid_argument(error);
  return answer;
}

}  // namespace

WhepSession::WhepSession(Pipeline& pipeline, std::string view, const std::string& peer, const std::string& offer_sdp,
                         const H264Offer& offer, const MediaSettings& settings)
    : pipeline_(pipeline), view_(std::move(view)) {
  // Stale frames too, as every video client gets them (docs/API.md); the frame says so.
  subscriber_ = pipeline_.subscribe(view_, peer, settings.key, settings.rate_hz, true);
  try {
    build(offer, settings);
    negotiate(offer_sdp);
  } catch (...) {
    if (media_) {
      gst_element_set_state(media_, GST_STATE_NULL);
      gst_object_unref(webrtc_);
      gst_object_unref(appsrc_);
      if (rtpbin_) gst_object_unref(rtpbin_);
      gst_object_unref(media_);
    }
    subscriber_.reset();
    throw;
  }
  thread_ = std::thread([this] {
    pthread_setname_np(pthread_self(), "whep-feed");
    feed();
  });
}

WhepSession::~WhepSession() {
  stop_ = true;
  subscriber_->close(ErrorKind::kCancelled, "the WebRTC viewer left");
  if (thread_.joinable()) thread_.join();
  // NULL first: webrtcbin's threads (ICE, DTLS) and the streaming threads end before our
  // callbacks' `this` and `subscriber_` go. (The subscription was released before this
  // once, and a viewer's key-frame request arriving in between, on the payloader's pad
  // probe, read the released subscriber: the daemon crashed when a browser that had just
  // frozen sent PLIs while its session ended.)
  gst_element_set_state(media_, GST_STATE_NULL);
  subscriber_.reset();  // leaves the view's group
  g_signal_handlers_disconnect_by_data(webrtc_, this);
  if (rtpbin_) {
    g_signal_handlers_disconnect_by_data(rtpbin_, this);
    gst_object_unref(rtpbin_);
  }
  GstBus* bus = gst_element_get_bus(media_);
  gst_bus_set_sync_handler(bus, nullptr, nullptr, nullptr);
  gst_object_unref(bus);
  gst_object_unref(webrtc_);
  gst_object_unref(appsrc_);
  gst_object_unref(media_);
}

void WhepSession::build(const H264Offer& offer, const MediaSettings& settings) {
  std::random_device random;
  rtp_offset_ = static_cast<uint32_t>(random());
  // The stream's SSRC in its caps from the start: webrtcbin writes the answer's a=ssrc lines
  // from them before any frame flows, and a browser attaches only the signalled SSRC's
  // pictures to the track (another SSRC it decodes, and shows nothing).
  const std::string ssrc = std::to_string(static_cast<uint32_t>(random()) | 1u);
  const std::string pt = std::to_string(offer.payload_type);
  // config-interval=0: the encoder sends SPS/PPS with every key frame already (issue 29:
  // inserting them again split key frames for some decoders). mtu 1200: room for the
  // SRTP, DTLS and TURN headers on any path.
  // The stream's caps say the profile the answer agreed (the offer's); the stream itself is
  // High profile whatever was offered (the shared encoder's), which a viewer's decoder takes
  // (WhepOffer's profile preference says why).
  const std::string profile =
      offer.profile_level_id.empty()
          ? ""
          : " ! capssetter caps=application/x-rtp,profile-level-id=(string)" + offer.profile_level_id;
  const std::string description =
      "appsrc name=src is-live=true format=time do-timestamp=false "
      "caps=video/x-h264,stream-format=byte-stream,alignment=au "
      "! rtph264pay name=pay config-interval=0 aggregate-mode=zero-latency mtu=1200 pt=" + pt +
      " timestamp-offset=" + std::to_string(rtp_offset_) + " ssrc=" + ssrc +
      " ! application/x-rtp,media=video,encoding-name=H264,clock-rate=90000,payload=" + pt + ",ssrc=(uint)" + ssrc +
      profile +
      " ! webrtcbin name=webrtc bundle-policy=max-bundle";
  GError* error = nullptr;
  media_ = gst_parse_launch(description.c_str(), &error);
  if (media_ == nullptr || error != nullptr) {
    const std::string why = error ? error->message : "unknown error";
    if (error) g_error_free(error);
    if (media_) gst_object_unref(media_);
    media_ = nullptr;
    throw std::runtime_error("cannot build the WebRTC media: " + why);
  }
  webrtc_ = gst_bin_get_by_name(GST_BIN(media_), "webrtc");
  appsrc_ = gst_bin_get_by_name(GST_BIN(media_), "src");
  if (!settings.stun_server.empty()) g_object_set(webrtc_, "stun-server", settings.stun_server.c_str(), nullptr);
  if (!settings.turn_server.empty()) g_object_set(webrtc_, "turn-server", settings.turn_server.c_str(), nullptr);
  GstWebRTCICE* ice = nullptr;
  g_object_get(webrtc_, "ice-agent", &ice, nullptr);
  settings_ports_ = {settings.min_udp_port, settings.max_udp_port};
  has_turn_server_ = !settings.turn_server.empty();
  if (ice) {
    if (settings.min_udp_port > 0) {
      g_object_set(ice, "min-rtp-port", guint(settings.min_udp_port), "max-rtp-port", guint(settings.max_udp_port),
                   nullptr);
    }
    // UDP only: ICE-TCP's passive candidates listened on TCP ports outside udp_ports, for a
    // path TURN serves better where UDP cannot pass.
    g_object_set(ice, "ice-tcp", FALSE, nullptr);
    // No UPnP-IGD: libnice asked the LAN's router (SSDP M-SEARCH on every interface) to open
    // the media port towards the internet, for every session.
    GObject* agent = nullptr;
    g_object_get(ice, "agent", &agent, nullptr);
    if (agent) {
      g_object_set(agent, "upnp", FALSE, nullptr);
      g_object_unref(agent);
    }
    gst_object_unref(ice);
  }
  // The transceiver the payloader's link made: it sends only, in the offer's payload type
  // and profile, with NACK retransmission where the viewer asked for it.
  GstWebRTCRTPTransceiver* transceiver = nullptr;
  g_signal_emit_by_name(webrtc_, "get-transceiver", 0, &transceiver);
  if (transceiver == nullptr) throw std::runtime_error("webrtcbin made no transceiver for the video");
  GstCaps* caps = gst_caps_new_simple("application/x-rtp", "media", G_TYPE_STRING, "video", "encoding-name",
                                      G_TYPE_STRING, "H264", "clock-rate", G_TYPE_INT, 90000, "payload", G_TYPE_INT,
                                      offer.payload_type, "packetization-mode", G_TYPE_STRING, "1", nullptr);
  if (!offer.profile_level_id.empty()) {
    gst_caps_set_simple(caps, "profile-level-id", G_TYPE_STRING, offer.profile_level_id.c_str(), nullptr);
  }
  g_object_set(transceiver, "direction", GST_WEBRTC_RTP_TRANSCEIVER_DIRECTION_SENDONLY, "codec-preferences", caps,
               "do-nack", gboolean(offer.nack), nullptr);
  gst_caps_unref(caps);
  gst_object_unref(transceiver);

  g_signal_connect_swapped(webrtc_, "notify::ice-connection-state", G_CALLBACK(+[](WhepSession* self) {
                             self->on_ice_state();
                           }),
                           this);
  // The viewer is alive while its RTCP comes (any packet: a receiver report, a NACK, a
  // PLI). Not from webrtcbin's stats: their remote-inbound entry moves on only while our
  // sending source counts as active, and after the daemon stalled a few seconds it did not
  // for a while, so a viewer that was fine was ended ~10 s after the stall in half the runs.
  rtpbin_ = gst_bin_get_by_name(GST_BIN(webrtc_), "rtpbin");
  if (rtpbin_ == nullptr) throw std::runtime_error("webrtcbin has no 'rtpbin' (an unexpected GStreamer version)");
  g_signal_connect_swapped(rtpbin_, "on-ssrc-active", G_CALLBACK(+[](WhepSession* self) {
                             self->on_viewer_rtcp(false);
                           }),
                           this);
  g_signal_connect_swapped(rtpbin_, "on-bye-ssrc", G_CALLBACK(+[](WhepSession* self) {
                             self->on_viewer_rtcp(true);
                           }),
                           this);
  GstBus* bus = gst_element_get_bus(media_);
  gst_bus_set_sync_handler(
      bus,
      [](GstBus*, GstMessage* message, gpointer data) -> GstBusSyncReply {
        if (GST_MESSAGE_TYPE(message) == GST_MESSAGE_ERROR) {
          auto* self = static_cast<WhepSession*>(data);
          GError* e = nullptr;
          gst_message_parse_error(message, &e, nullptr);
          std::lock_guard lock(self->state_mutex_);
          if (self->media_error_.empty()) self->media_error_ = std::string("media failed: ") + (e ? e->message : "?");
          if (e) g_error_free(e);
        }
        gst_message_unref(message);  // GST_BUS_DROP: the handler owns it (each holds its element)
        return GST_BUS_DROP;
      },
      this, nullptr);
  gst_object_unref(bus);
  GstElement* pay = gst_bin_get_by_name(GST_BIN(media_), "pay");
  GstPad* pay_src = gst_element_get_static_pad(pay, "src");
  gst_pad_add_probe(
      pay_src, GST_PAD_PROBE_TYPE_EVENT_UPSTREAM,
      [](GstPad*, GstPadProbeInfo* info, gpointer data) -> GstPadProbeReturn {
        GstEvent* event = GST_PAD_PROBE_INFO_EVENT(info);
        const GstStructure* s = event ? gst_event_get_structure(event) : nullptr;
        if (GST_EVENT_TYPE(event) == GST_EVENT_CUSTOM_UPSTREAM && s && gst_structure_has_name(s, "GstForceKeyUnit")) {
          static_cast<WhepSession*>(data)->on_force_key_unit();
        }
        return GST_PAD_PROBE_OK;
      },
      this, nullptr);
  gst_object_unref(pay_src);
  gst_object_unref(pay);

  if (gst_element_set_state(media_, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE) {
    throw std::runtime_error("the WebRTC media did not start (GStreamer's webrtcbin, nice and dtls elements: "
                             "gstreamer1.0-plugins-bad and gstreamer1.0-nice)");
  }
  // Running time 0 of the media is this instant: frames carry their capture time from it.
  const GstClockTime running = gst_element_get_current_running_time(media_);
  capture_epoch_us_ = unix_us_now() - (GST_CLOCK_TIME_IS_VALID(running) ? int64_t(running / 1000) : 0);
}

void WhepSession::negotiate(const std::string& offer_sdp) {
  GstSDPMessage* sdp = nullptr;
  if (gst_sdp_message_new_from_text(offer_sdp.c_str(), &sdp) != GST_SDP_OK) {
    throw std::invalid_argument("the body is not an SDP offer");
  }
  GstWebRTCSessionDescription* offer = gst_webrtc_session_description_new(GST_WEBRTC_SDP_TYPE_OFFER, sdp);
  try {
    negotiate_step(webrtc_, "set-remote-description", offer, nullptr);
  } catch (...) {
    gst_webrtc_session_description_free(offer);
    throw;
  }
  gst_webrtc_session_description_free(offer);
  GstWebRTCSessionDescription* answer = negotiate_step(webrtc_, "create-answer", nullptr, "answer");
  try {
    negotiate_step(webrtc_, "set-local-description", answer, nullptr);
  } catch (...) {
    gst_webrtc_session_description_free(answer);
    throw;
  }
  gst_webrtc_session_description_free(answer);
  // The whole answer at once (WHEP's trickle is optional): wait for the candidates.
  const auto deadline = Clock::now() + kGatherTimeout;
  while (Clock::now() < deadline) {
    GstWebRTCICEGatheringState gathering = GST_WEBRTC_ICE_GATHERING_STATE_NEW;
    g_object_get(webrtc_, "ice-gathering-state", &gathering, nullptr);
    if (gathering == GST_WEBRTC_ICE_GATHERING_STATE_COMPLETE) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  GstWebRTCSessionDescription* local = nullptr;
  g_object_get(webrtc_, "local-description", &local, nullptr);
  if (local == nullptr) throw std::runtime_error("webrtcbin has no local description after the answer");
  gchar* text = gst_sdp_message_as_text(local->sdp);
  answer_ = text ? text : "";
  g_free(text);
  gst_webrtc_session_description_free(local);
  // An answer without a candidate cannot connect: the viewer would wait for ICE in vain.
  if (answer_.find("a=candidate:") == std::string::npos) throw PipelineError(ErrorKind::kUnavailable, no_candidate_reason());
  relay_missing_ = has_turn_server_ && answer_.find(" typ relay") == std::string::npos;
}

std::string WhepSession::no_candidate_reason() const {
  // libnice offers no loopback candidate: a host whose only interface is loopback has none.
  bool other_interface = false;
  ifaddrs* interfaces = nullptr;
  if (getifaddrs(&interfaces) == 0) {
    for (const ifaddrs* i = interfaces; i != nullptr; i = i->ifa_next) {
      if (i->ifa_addr && (i->ifa_addr->sa_family == AF_INET || i->ifa_addr->sa_family == AF_INET6) &&
          (i->ifa_flags & IFF_UP) && !(i->ifa_flags & IFF_LOOPBACK)) {
        other_interface = true;
      }
    }
    freeifaddrs(interfaces);
  }
  if (!other_interface) {
    return "no ICE candidate for the media: this host has no network interface up but loopback (WebRTC needs one "
           "the viewer can reach over UDP)";
  }
  if (settings_ports_.first > 0) {
    return "no ICE candidate for the media: no free UDP port in web.webrtc.udp_ports (" +
           std::to_string(settings_ports_.first) + "-" + std::to_string(settings_ports_.second) +
           "; each viewer holds one): widen the range or end a session";
  }
  return "no ICE candidate for the media: libnice found no UDP port to bind";
}

void WhepSession::on_ice_state() {
  GstWebRTCICEConnectionState state = GST_WEBRTC_ICE_CONNECTION_STATE_NEW;
  g_object_get(webrtc_, "ice-connection-state", &state, nullptr);
  std::lock_guard lock(state_mutex_);
  if (state == ice_state_) return;
  ice_state_ = state;
  ice_state_since_ = Clock::now();
  if (state == GST_WEBRTC_ICE_CONNECTION_STATE_CONNECTED || state == GST_WEBRTC_ICE_CONNECTION_STATE_COMPLETED) {
    if (!ever_connected_) viewer_rtcp_at_ = Clock::now();
    ever_connected_ = true;
  }
}

void WhepSession::on_force_key_unit() {
  if (stop_) return;  // ending: the feed no longer reads
  const int64_t now = Clock::now().time_since_epoch().count();
  int64_t last = last_key_request_ns_.load();
  const int64_t interval = std::chrono::duration_cast<Clock::duration>(kKeyRequestInterval).count();
  if (now - last < interval || !last_key_request_ns_.compare_exchange_strong(last, now)) return;
  ++key_frames_asked_;
  if (const auto& video = subscriber_->video()) video->request_key_frame();
}

void WhepSession::on_viewer_rtcp(bool bye) {
  std::lock_guard lock(state_mutex_);
  viewer_rtcp_at_ = Clock::now();
  viewer_said_bye_ = viewer_said_bye_ || bye;
}

bool WhepSession::connected() const {
  std::lock_guard lock(state_mutex_);
  return ice_state_ == GST_WEBRTC_ICE_CONNECTION_STATE_CONNECTED ||
         ice_state_ == GST_WEBRTC_ICE_CONNECTION_STATE_COMPLETED;
}

std::string WhepSession::gone(Clock::time_point now, Clock::duration connect_timeout,
                              Clock::duration disconnected_grace) const {
  const auto seconds = [](Clock::duration d) {
    return std::to_string(std::chrono::duration_cast<std::chrono::seconds>(d).count()) + " s";
  };
  std::lock_guard lock(state_mutex_);
  if (!media_error_.empty()) return media_error_;
  if (viewer_said_bye_) return "the viewer left (RTCP BYE)";
  switch (ice_state_) {
    case GST_WEBRTC_ICE_CONNECTION_STATE_FAILED: return "ICE failed (the viewer is unreachable over UDP)";
    case GST_WEBRTC_ICE_CONNECTION_STATE_CLOSED: return "ICE closed";
    case GST_WEBRTC_ICE_CONNECTION_STATE_DISCONNECTED:
      if (now - ice_state_since_ > disconnected_grace) return "disconnected for over " + seconds(disconnected_grace);
      break;
    default: break;
  }
  // A viewer that vanished without DELETE: ICE as the answering side does not notice (no
  // consent checks in this webrtcbin), but its RTCP (receiver reports, every second or so)
  // stops. Judged only while frames flow (a viewer may stop reporting on a silent stream).
  if (ever_connected_ && now - viewer_rtcp_at_ > disconnected_grace && now - last_push_ < std::chrono::seconds(2)) {
    return "no receiver report (RTCP) from the viewer for over " + seconds(disconnected_grace);
  }
  if (!media_started_ && now - created_ > connect_timeout) {
    return std::string(ever_connected_ ? "DTLS" : "ICE") + " did not connect within " + seconds(connect_timeout) +
           " of the answer";
  }
  return "";
}

bool WhepSession::push(const v1::Frame& frame) {
  const std::string& data = frame.data();
  GstBuffer* buffer = gst_buffer_new_memdup(data.data(), data.size());
  if (!frame.key_frame()) GST_BUFFER_FLAG_SET(buffer, GST_BUFFER_FLAG_DELTA_UNIT);
  // The capture time on the media's running-time axis (see capture_epoch_us): the RTP
  // timestamp then says when the picture was captured. A cached key frame from before the
  // session started is stamped 0.
  const int64_t at_us = std::max<int64_t>(0, capture_us(frame) - capture_epoch_us_);
  GST_BUFFER_PTS(buffer) = GstClockTime(at_us) * 1000;
  if (gst_app_src_push_buffer(GST_APP_SRC(appsrc_), buffer) != GST_FLOW_OK) return false;
  ++frames_sent_;
  std::lock_guard lock(state_mutex_);
  last_push_ = Clock::now();
  return true;
}

bool WhepSession::media_ready() const {
  if (!connected()) return false;
  GstWebRTCRTPTransceiver* transceiver = nullptr;
  g_signal_emit_by_name(webrtc_, "get-transceiver", 0, &transceiver);
  if (transceiver == nullptr) return false;
  GstWebRTCRTPSender* sender = nullptr;
  g_object_get(transceiver, "sender", &sender, nullptr);
  gst_object_unref(transceiver);
  if (sender == nullptr) return false;
  GstWebRTCDTLSTransport* transport = nullptr;
  g_object_get(sender, "transport", &transport, nullptr);
  gst_object_unref(sender);
  if (transport == nullptr) return false;
  GstWebRTCDTLSTransportState state = GST_WEBRTC_DTLS_TRANSPORT_STATE_NEW;
  g_object_get(transport, "state", &state, nullptr);
  gst_object_unref(transport);
  return state == GST_WEBRTC_DTLS_TRANSPORT_STATE_CONNECTED;
}

void WhepSession::feed() {
  // Until ICE and DTLS are up webrtcbin drops what it is given: frames wait in the slot
  // (replaced, not counted: the viewer has not started), and the first one sent is a key
  // frame asked for then, so the viewer's first picture is the present, not a cached key
  // frame followed by deltas whose references it never got.
  while (!stop_ && !media_ready()) {
    const auto frame = subscriber_->take(std::chrono::milliseconds(50));
    if (frame && !*frame) return view_went_away();
  }
  if (stop_) return;
  media_started_ = true;
  subscriber_->starts_reading();
  if (const auto& video = subscriber_->video()) video->request_key_frame();
  const auto usable = [&](const v1::Frame& frame) {
    if (awaiting_key_ && !frame.key_frame()) return false;  // it depends on frames the viewer did not get
    awaiting_key_ = false;
    return true;
  };
  while (!stop_) {
    const auto frame = subscriber_->take(std::chrono::milliseconds(100));
    if (!frame) continue;
    if (!*frame) return view_went_away();  // the view was deleted, or the daemon stops
    if (!subscriber_->hand_over(**frame)) continue;
    if (gst_app_src_get_current_level_bytes(GST_APP_SRC(appsrc_)) > kMaxQueuedBytes) {
      awaiting_key_ = true;  // the link is slower than the stream: skip to a fresh key frame
      if (const auto& video = subscriber_->video()) video->request_key_frame();
      continue;
    }
    if (!usable(**frame)) continue;
    if (!push(**frame)) break;  // the media is going away
  }
}

void WhepSession::view_went_away() {
  std::lock_guard lock(state_mutex_);
  if (media_error_.empty()) media_error_ = "the view went away: " + subscriber_->close_reason();
}

}  // namespace omniview::webrtc
