#include "server/webrtc/whep_server.h"

#include <gst/gst.h>

#include <iostream>
#include <random>

#include "server/pipeline/frame_encoder.h"
#include "server/status/failure.h"
#include "server/webrtc/whep_offer.h"
#include "server/webrtc/whep_session.h"

namespace omniview::webrtc {
namespace {

// A viewer whose ICE never connects (it vanished, or UDP cannot pass) is freed this long
// after its answer; one that lost its connection, this long after (ICE may recover
// meanwhile: a Wi-Fi roam). Both "within seconds", as the sessions' slots are few.
constexpr auto kConnectTimeout = std::chrono::seconds(15);
constexpr auto kDisconnectedGrace = std::chrono::seconds(10);

// GStreamer once per process (RTSP may have done it already: gst_init is idempotent), and
// the elements a WebRTC media needs, each with the Debian package that has it.
std::string check_gstreamer() {
  GError* e = nullptr;
  if (!gst_init_check(nullptr, nullptr, &e)) {
    std::string why = std::string("cannot start GStreamer: ") + (e ? e->message : "unknown error");
    if (e) g_error_free(e);
    return why;
  }
  const std::pair<const char*, const char*> needed[] = {
      {"appsrc", "gstreamer1.0-plugins-base"},  {"rtph264pay", "gstreamer1.0-plugins-good"},
      {"webrtcbin", "gstreamer1.0-plugins-bad"}, {"dtlssrtpenc", "gstreamer1.0-plugins-bad"},
      {"srtpenc", "gstreamer1.0-plugins-bad"},   {"nicesink", "gstreamer1.0-nice"},
      {"rtpbin", "gstreamer1.0-plugins-good"},   {"capssetter", "gstreamer1.0-plugins-good"}};
  for (const auto& [element, package] : needed) {
    GstElementFactory* factory = gst_element_factory_find(element);
    if (factory == nullptr) return std::string("GStreamer's '") + element + "' element is missing: install " + package;
    gst_object_unref(factory);
  }
  return "";
}

std::string new_session_id() {
  static std::mutex mutex;
  static std::random_device random;
  std::lock_guard lock(mutex);
  static const char* const kHex = "0123456789abcdef";
  std::string id;
  for (int i = 0; i < 4; ++i) {
    uint32_t v = random();
    for (int j = 0; j < 8; ++j, v >>= 4) id += kHex[v & 15];
  }
  return id;  // 128 random bits: not guessable from another session's
}

std::string no_session(const std::string& view, const std::string& id) {
  return "no WebRTC session /whep/" + view + "/" + id + " (ended, or never made)";
}

HttpReply text(int status, std::string body) {
  HttpReply a;
  a.status = status;
  a.body = std::move(body) + "\n";
  return a;
}

}  // namespace

WhepServer::WhepServer(const WebRtcConfig& config, const Limits& limits, Pipeline& pipeline)
    : config_(config), limits_(limits), pipeline_(pipeline), unavailable_(check_gstreamer()) {
  sweeper_ = std::thread([this] { sweep(); });
}

WhepServer::~WhepServer() {
  std::map<std::string, Entry> ending;
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    ending.swap(sessions_);
  }
  wake_.notify_all();
  sweeper_.join();
  ending.clear();  // each session leaves its view's group
}

std::vector<std::pair<std::string, std::string>> WhepServer::ice_server_links() const {
  std::vector<std::pair<std::string, std::string>> links;
  // RFC 8288 links as WHEP says (rel="ice-server"); a TURN server's credentials too, as
  // the viewer needs them (the client already holds a token to the daemon).
  const auto strip = [](const std::string& url, const std::string& scheme) { return url.substr(scheme.size() + 3); };
  if (!config_.stun_server.empty()) {
    links.emplace_back("Link", "<stun:" + strip(config_.stun_server, "stun") + ">; rel=\"ice-server\"");
  }
  if (!config_.turn_server.empty()) {
    const bool tls = config_.turn_server.rfind("turns://", 0) == 0;
    std::string rest = strip(config_.turn_server, tls ? "turns" : "turn");
    std::string user, password;
    if (const auto at = rest.rfind('@'); at != std::string::npos) {
      const std::string credentials = rest.substr(0, at);
      rest = rest.substr(at + 1);
      const auto colon = credentials.find(':');
      user = credentials.substr(0, colon);
      if (colon != std::string::npos) password = credentials.substr(colon + 1);
    }
    links.emplace_back("Link", std::string("<") + (tls ? "turns:" : "turn:") + rest + ">; rel=\"ice-server\"; " +
                                   "username=\"" + user + "\"; credential=\"" + password +
                                   "\"; credential-type=\"password\"");
  }
  return links;
}

HttpReply WhepServer::create(const std::string& view, const std::string& content_type, const std::string& offer,
                              const std::string& client, const std::string& peer, const Caller& who) {
  if (!unavailable_.empty()) return text(503, "WebRTC is not available on this daemon: " + unavailable_);
  const std::string type = content_type.substr(0, content_type.find(';'));
  if (type != "application/sdp") {
    return refuse(peer, 415, "a WHEP offer is sent as 'Content-Type: application/sdp', not '" + content_type + "'");
  }
  H264Offer h264;
  try {
    h264 = read_h264_offer(offer);
  } catch (const CodecNotOffered& e) {
    return refuse(peer, 406, e.what());
  } catch (const std::invalid_argument& e) {
    return refuse(peer, 400, e.what());
  }
  const int max_total = std::min(config_.max_sessions, limits_.max_streams);
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return text(503, "omniviewd is shutting down");
    if (reserved_total_ >= max_total) {
      return refuse(peer, 503, "this daemon serves at most " + std::to_string(max_total) +
                                   " WebRTC viewers at once (web.webrtc.max_sessions, limits.max_streams); try again later");
    }
    if (reserved_[client] >= config_.max_sessions_per_client) {
      return refuse(peer, 503, "at most " + std::to_string(config_.max_sessions_per_client) +
                                   " WebRTC viewers from one address (web.webrtc.max_sessions_per_client): end one "
                                   "(DELETE its Location) first");
    }
    ++reserved_[client];
    ++reserved_total_;
  }
  const auto release = [&] {
    std::lock_guard lock(mutex_);
    if (--reserved_[client] == 0) reserved_.erase(client);
    --reserved_total_;
  };
  MediaSettings settings;
  settings.key = encoding_key(v1::H264, config_.quality, false, config_.max_bitrate_kbps);
  settings.rate_hz = limits_.max_rate_hz;
  settings.stun_server = config_.stun_server;
  settings.turn_server = config_.turn_server;
  settings.min_udp_port = config_.min_udp_port;
  settings.max_udp_port = config_.max_udp_port;
  // The session's id comes first: the viewer's name in the status carries it, so a status
  // line and the log's "session 1a2b3c4d" are told together (the POST's TCP port, which
  // the name carried, meant nothing once the POST's connection closed).
  const std::string id = new_session_id();
  std::shared_ptr<WhepSession> session;
  try {
    session = std::make_shared<WhepSession>(pipeline_, view, "webrtc:" + client + "#" + id.substr(0, 8),
                                            without_mdns_candidates(offer), h264, settings);
  } catch (...) {
    release();
    // webrtcbin's refusals of the offer come as std::invalid_argument: 400 like the parser's.
    const Failure failure = current_failure();
    if (failure.kind == ErrorKind::kInternal) {  // ours: every one logged
      std::cerr << "omniviewd: webrtc: " << peer << ": " << failure.message << std::endl;
      return text(http_status(failure.kind), failure.message);
    }
    return refuse(peer, http_status(failure.kind), failure.message);
  }
  HttpReply a;
  a.status = 201;
  a.content_type = "application/sdp";
  a.body = session->answer_sdp();
  a.headers.emplace_back("Location", "/whep/" + view + "/" + id);
  a.headers.emplace_back("ETag", "\"" + id + "\"");
  // The RTP timestamps' tie to capture time (whep_session.h): the console's latency figure.
  a.headers.emplace_back("Omniview-Capture-Clock", "rtp=" + std::to_string(session->rtp_offset()) +
                                                       "; unix_us=" + std::to_string(session->capture_epoch_us()));
  for (auto& link : ice_server_links()) a.headers.push_back(std::move(link));
  const bool relay_missing = session->relay_missing();
  {
    std::lock_guard lock(mutex_);
    if (stopping_) {
      release();
      return text(503, "omniviewd is shutting down");
    }
    sessions_.emplace(id, Entry{view, client, who.label, std::move(session)});
  }
  std::cerr << "omniviewd: webrtc: " << peer << " watches '" << view << "' (session " << id.substr(0, 8) << ")"
            << std::endl;
  if (relay_missing && relay_warning_.admit("turn").has_value()) {
    // Viewers on the LAN still connect; those that need the relay will not.
    std::cerr << "omniviewd: webrtc: the TURN server (web.webrtc.turn_server) gave no relay candidate within "
              << std::chrono::duration_cast<std::chrono::seconds>(WhepSession::kGatherTimeout).count()
              << " s: unreachable, or it refused the configured user and password (see its log)" << std::endl;
  }
  return a;
}

std::string WhepServer::unknown(const std::string& view, const std::string& id) const {
  if (!id.empty()) {
    std::lock_guard lock(mutex_);
    const auto it = sessions_.find(id);
    return it == sessions_.end() || it->second.view != view ? no_session(view, id) : "";
  }
  try {
    pipeline_.get_view(view);
    return "";
  } catch (const PipelineError& e) {
    return e.what();
  }
}

HttpReply WhepServer::remove(const std::string& view, const std::string& id, const std::string& peer,
                             const Caller& who) {
  std::shared_ptr<WhepSession> ending;
  {
    std::lock_guard lock(mutex_);
    const auto it = sessions_.find(id);
    if (it == sessions_.end() || it->second.view != view) {
      return text(404, no_session(view, id));
    }
    if (who.role != Role::kOperator && who.label != it->second.owner) {
      return refuse(peer, 403, "this session was made with another token: that token or an operator's ends it");
    }
    ending = std::move(it->second.session);
    if (--reserved_[it->second.client] == 0) reserved_.erase(it->second.client);
    --reserved_total_;
    sessions_.erase(it);
  }
  ending.reset();  // outside the lock: it waits for its feed thread and the media's
  std::cerr << "omniviewd: webrtc: session " << id.substr(0, 8) << " on '" << view << "' ended: DELETE from " << peer
            << std::endl;
  return text(200, "session ended");
}

HttpReply WhepServer::refuse(const std::string& peer, int status, std::string why) {
  if (const auto left_out = refusals_.admit(peer)) {
    std::cerr << "omniviewd: webrtc: refused " << peer << ": " << why
              << (*left_out ? " (and " + std::to_string(*left_out) + " more refusals from this host not logged)" : "")
              << std::endl;
  }
  return text(status, std::move(why));
}

size_t WhepServer::sessions() const {
  std::lock_guard lock(mutex_);
  return sessions_.size();
}

void WhepServer::sweep() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, std::chrono::milliseconds(500));
    if (stopping_) break;
    std::vector<std::pair<std::string, std::shared_ptr<WhepSession>>> now_serving;
    for (const auto& [id, entry] : sessions_) now_serving.emplace_back(id, entry.session);
    lock.unlock();
    std::vector<std::pair<std::string, std::string>> over;  // id, why
    for (const auto& [id, session] : now_serving) {
      const auto now = WhepSession::Clock::now();
      std::string why = session->gone(now, kConnectTimeout, kDisconnectedGrace);
      if (!why.empty()) over.emplace_back(id, std::move(why));
    }
    now_serving.clear();  // a session DELETEd meanwhile ends here, outside the lock
    std::vector<std::shared_ptr<WhepSession>> ending;
    lock.lock();
    for (const auto& [id, why] : over) {
      const auto it = sessions_.find(id);
      if (it == sessions_.end()) continue;  // DELETEd meanwhile
      std::cerr << "omniviewd: webrtc: session " << id.substr(0, 8) << " on '" << it->second.view
                << "' ended: " << why << std::endl;
      ending.push_back(std::move(it->second.session));
      if (--reserved_[it->second.client] == 0) reserved_.erase(it->second.client);
      --reserved_total_;
      sessions_.erase(it);
    }
    lock.unlock();
    ending.clear();  // each waits for its threads
    lock.lock();
  }
}

}  // namespace omniview::webrtc
