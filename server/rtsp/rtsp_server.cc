#include "server/rtsp/rtsp_server.h"

#include <gst/rtsp-server/rtsp-server.h>
#include <pthread.h>

#include <chrono>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

#include "server/auth/refusal_log.h"
#include "server/exposure/host_port.h"
#include "server/pipeline/frame_encoder.h"
#include "server/rtsp/connection_limits.h"
#include "server/rtsp/rtsp_auth.h"
#include "server/rtsp/rtsp_feed.h"
#include "server/video/h264_encoder.h"

namespace omniview {

namespace {

constexpr const char* kUser = "omniview";
constexpr const char* kRole = "viewer";
constexpr guint kMountSyncMs = 500;  // views created or deleted through the API show up this fast
constexpr guint kIdleSweepMs = 1000;  // how often idle connections are looked for

// appsrc's caps say what we push: Annex-B access units. h264parse puts SPS/PPS into the
// caps for the SDP. Every key frame already carries its SPS/PPS (x264 repeats them), so
// rtph264pay adds none (config-interval 0): with -1 it put another pair before each IDR
// *slice*, and ffmpeg-based players (ffplay, mpv) then decoded each key frame of several
// slices as two half pictures (issue 29).
constexpr const char* kLaunch =
    "( appsrc name=src is-live=true do-timestamp=true format=time "
    "caps=video/x-h264,stream-format=byte-stream,alignment=au "
    "! h264parse ! rtph264pay name=pay0 pt=96 config-interval=0 )";

void init_gstreamer() {
  static std::once_flag once;
  static std::string error;
  std::call_once(once, [] {
    GError* e = nullptr;
    if (!gst_init_check(nullptr, nullptr, &e)) {
      error = std::string("cannot start GStreamer: ") + (e ? e->message : "unknown error");
      if (e) g_error_free(e);
    }
  });
  if (!error.empty()) throw std::runtime_error(error);
  for (const auto& [element, package] :
       std::vector<std::pair<const char*, const char*>>{{"appsrc", "gstreamer1.0-plugins-base"},
                                                        {"h264parse", "gstreamer1.0-plugins-bad"},
                                                        {"rtph264pay", "gstreamer1.0-plugins-good"}}) {
    GstElementFactory* factory = gst_element_factory_find(element);
    if (factory == nullptr) {
      throw std::runtime_error(std::string("RTSP needs GStreamer's '") + element + "' element: install " + package);
    }
    gst_object_unref(factory);
  }
}

std::string url_host(const std::string& listen) {
  const auto hp = split_host_port(listen);
  std::string host = hp ? hp->host : listen;
  if (host == "0.0.0.0" || host == "::" || host == "[::]") host = "HOST";  // any of this machine's addresses
  if (hp && hp->bracketed) host = "[" + host + "]";
  return host;
}

}  // namespace

// What a media of one view needs when a client asks for it (the factory's signal data).
struct MountContext {
  Pipeline* pipeline;
  std::string view;
  EncodingKey key;
  double rate_hz;
};

// What the daemon keeps about one open connection (the client object's data): its slot
// under the connection caps, and since when it has had no stream playing. Only the
// server's thread touches it (clients are served there).
struct ClientState {
  std::unique_ptr<ConnectionLimits::Slot> slot;
  std::chrono::steady_clock::time_point idle_since = std::chrono::steady_clock::now();
  bool played = false;  // a PLAY of its own answered 200 (not a session id it merely named)
  std::set<std::string> own_sessions;  // ids of the sessions its SETUPs made
  std::optional<std::chrono::steady_clock::time_point> shut_down;  // idle: its socket shut down then
};

struct RtspServer::Impl {
  Pipeline& pipeline;
  RtspConfig config;
  std::shared_ptr<ConnectionLimits> limits;
  std::unique_ptr<ConnectionLimits::Slot> admitted;  // the slot of the connection being accepted
  RefusalLog refusals;
  EncodingKey key;
  double rate_hz = 0;
  std::string scheme = "rtsp";
  GstRTSPServer* server = nullptr;
  GstRTSPMountPoints* mounts = nullptr;
  GstRTSPAuth* auth = nullptr;
  GMainContext* context = nullptr;
  GMainLoop* loop = nullptr;
  guint attach_id = 0;
  std::thread thread;
  int port = 0;
  std::mutex mutex;
  std::set<std::string> mounted;  // view names
  std::set<std::string> unservable;  // views left unmounted (said once each); the sync's own
  bool stopped = false;

  explicit Impl(Pipeline& p) : pipeline(p) {}

  void mount(const std::string& view);
  void sync_mounts();
  bool admit(GstRTSPContext* ctx);
  void connected(GstRTSPClient* client);
  void unauthorized(GstRTSPContext* ctx);
  void untie_foreign_session(GstRTSPContext* ctx);
  GstRTSPStatusCode check_source(GstRTSPContext* ctx);
  void close_idle_clients();
};

namespace {

void destroy_feed(gpointer feed) { delete static_cast<RtspFeed*>(feed); }

// A client asked for a view: its media gets a feed of its own (non-shared media), whose
// subscription asks the group's encoder for a key frame, so the client starts at once.
void on_media_configure(GstRTSPMediaFactory*, GstRTSPMedia* media, gpointer data) {
  const auto* mount = static_cast<const MountContext*>(data);
  GstElement* bin = gst_rtsp_media_get_element(media);
  GstElement* appsrc = gst_bin_get_by_name_recurse_up(GST_BIN(bin), "src");
  gst_object_unref(bin);
  if (appsrc == nullptr) return;
  try {
    auto* feed = new RtspFeed(*mount->pipeline, mount->view, mount->key, mount->rate_hz, appsrc);
    g_object_set_data_full(G_OBJECT(media), "omniview-feed", feed, destroy_feed);
  } catch (const std::exception& e) {
    // A view deleted between the mount and the request: the media ends at once.
    std::cerr << "omniviewd: rtsp: view '" << mount->view << "': " << e.what() << std::endl;
    gst_element_send_event(appsrc, gst_event_new_eos());
  }
  gst_object_unref(appsrc);
}

std::string peer_ip(GstRTSPConnection* conn) {
  const gchar* ip = conn != nullptr ? gst_rtsp_connection_get_ip(conn) : nullptr;
  return ip != nullptr ? ip : "unknown";
}

void destroy_client_state(gpointer state) { delete static_cast<ClientState*>(state); }

ClientState* client_state(GstRTSPClient* client) {
  return static_cast<ClientState*>(g_object_get_data(G_OBJECT(client), "omniview-state"));
}

RtspFeed* media_feed(GstRTSPContext* ctx) {
  if (ctx == nullptr || ctx->media == nullptr) return nullptr;
  return static_cast<RtspFeed*>(g_object_get_data(G_OBJECT(ctx->media), "omniview-feed"));
}

void on_play_request(GstRTSPClient* client, GstRTSPContext* ctx, gpointer) {
  if (ClientState* state = client_state(client)) state->played = true;
  if (RtspFeed* feed = media_feed(ctx)) feed->set_playing(true);
}

void on_pause_request(GstRTSPClient*, GstRTSPContext* ctx, gpointer) {
  if (RtspFeed* feed = media_feed(ctx)) feed->set_playing(false);
}

// A session the request's connection did not make (another client's, or one it made on an
// earlier connection).
bool foreign_session(GstRTSPContext* ctx) {
  const ClientState* state = ctx->client != nullptr ? client_state(ctx->client) : nullptr;
  return state == nullptr || !state->own_sessions.count(gst_rtsp_session_get_sessionid(ctx->session));
}

void on_new_session(GstRTSPClient* client, GstRTSPSession* session, gpointer) {
  if (ClientState* state = client_state(client)) state->own_sessions.insert(gst_rtsp_session_get_sessionid(session));
}

GstRTSPFilterResult find_playing_media(GstRTSPSession*, GstRTSPSessionMedia* media, gpointer playing) {
  if (gst_rtsp_session_media_get_rtsp_state(media) == GST_RTSP_STATE_PLAYING) *static_cast<bool*>(playing) = true;
  return GST_RTSP_FILTER_KEEP;
}

GstRTSPFilterResult find_playing_session(GstRTSPClient*, GstRTSPSession* session, gpointer playing) {
  gst_rtsp_session_filter(session, find_playing_media, playing);
  return GST_RTSP_FILTER_KEEP;
}

}  // namespace

// Runs on the server's thread, for each new TCP connection, before the library makes a
// client of it: refused, the connection is closed at once (no RTSP reply: there is no
// request yet to answer).
bool RtspServer::Impl::admit(GstRTSPContext* ctx) {
  const std::string host = peer_ip(ctx->conn);
  std::string why;
  admitted = limits->acquire(host, &why);
  if (admitted) return true;
  if (const auto left_out = refusals.admit(host)) {
    std::cerr << "omniviewd: rtsp: refused a connection from " << host << ": " << why
              << (*left_out ? " (and " + std::to_string(*left_out) + " more refusals from this host not logged)" : "")
              << std::endl;
  }
  return false;
}

// A connection accepted (after admit said yes): it takes the slot admit reserved, freed
// with the client object.
void RtspServer::Impl::connected(GstRTSPClient* client) {
  auto* state = new ClientState;
  state->slot = std::move(admitted);
  g_object_set_data_full(G_OBJECT(client), "omniview-state", state, destroy_client_state);
  g_signal_connect(client, "play-request", G_CALLBACK(on_play_request), nullptr);
  g_signal_connect(client, "pause-request", G_CALLBACK(on_pause_request), nullptr);
  g_signal_connect(client, "new-session", G_CALLBACK(on_new_session), nullptr);
  g_signal_connect(client, "pre-describe-request",
                   G_CALLBACK(+[](GstRTSPClient*, GstRTSPContext* ctx, gpointer data) {
                     return static_cast<Impl*>(data)->check_source(ctx);
                   }),
                   this);
}

// A DESCRIBE waits for the view's first key frame (its SPS/PPS go into the SDP), on the
// thread that serves every client. A view whose source has delivered nothing and is not
// connected (a robot not reached since the daemon started, a camera unplugged) would hold
// them all for the library's 20 s: 503 at once instead, the source's own message logged.
// A connected source that has not sent yet (nobody watched until now) is waited for.
GstRTSPStatusCode RtspServer::Impl::check_source(GstRTSPContext* ctx) {
  if (ctx->uri == nullptr || ctx->uri->abspath == nullptr) return GST_RTSP_STS_OK;
  std::string view = ctx->uri->abspath;
  view = view.substr(view.find_first_not_of('/') == std::string::npos ? view.size() : view.find_first_not_of('/'));
  view = view.substr(0, view.find('/'));
  try {
    std::string source = pipeline.get_view(view).spec().source();
    for (const auto& s : pipeline.report().sources) {
      if (!source.empty() && s.name != source) continue;
      if (s.connected || s.last_frame_age_s >= 0) return GST_RTSP_STS_OK;
      if (refusals.admit(peer_ip(ctx->conn))) {  // rate-limited per host, as the 401s
        std::cerr << "omniviewd: rtsp: DESCRIBE /" << view << " answered 503: source '" << s.name
                  << "' has sent no images yet" << (s.message.empty() ? "" : " (" + s.message + ")") << std::endl;
      }
      return GST_RTSP_STS_SERVICE_UNAVAILABLE;
    }
  } catch (const std::exception&) {
    // No such view (the library answers 404), or the daemon stopping.
  }
  return GST_RTSP_STS_OK;
}

// The library looks a request's session id up before any check and ties the session to
// the connection, which would stop the session's streams when that connection closes: a
// session this connection did not make, named in a refused request, is untied again.
void RtspServer::Impl::untie_foreign_session(GstRTSPContext* ctx) {
  if (ctx->session == nullptr || ctx->client == nullptr || !foreign_session(ctx)) return;
  gst_rtsp_client_session_filter(
      ctx->client,
      [](GstRTSPClient*, GstRTSPSession* session, gpointer named) {
        return session == named ? GST_RTSP_FILTER_REMOVE : GST_RTSP_FILTER_KEEP;
      },
      ctx->session);
}

// A request answered 401: the session it named untied, then the log, rate-limited per
// host like the gRPC port's refusals; the path only (the request line carries no
// credentials, the Authorization header is never logged).
void RtspServer::Impl::unauthorized(GstRTSPContext* ctx) {
  untie_foreign_session(ctx);
  const std::string host = peer_ip(ctx->conn);
  const auto left_out = refusals.admit(host);
  if (!left_out) return;
  GstRTSPMethod method = GST_RTSP_INVALID;
  const gchar* uri = nullptr;
  if (ctx->request != nullptr) gst_rtsp_message_parse_request(ctx->request, &method, &uri, nullptr);
  const gchar* path = ctx->uri != nullptr && ctx->uri->abspath != nullptr ? ctx->uri->abspath : "?";
  gchar* credentials = nullptr;
  const bool sent = ctx->request != nullptr &&
                    gst_rtsp_message_get_header(ctx->request, GST_RTSP_HDR_AUTHORIZATION, &credentials, 0) == GST_RTSP_OK;
  std::cerr << "omniviewd: rtsp: refused " << gst_rtsp_method_as_text(method) << " " << path << " from " << host
            << ": " << (sent ? "wrong credentials" : "no credentials") << " (401)"
            << (*left_out ? " (and " + std::to_string(*left_out) + " more refusals from this host not logged)" : "")
            << std::endl;
}

// A connection with nothing playing for rtsp.idle_timeout_s is closed: one that never
// authenticates, stops after DESCRIBE, or stays paused gives its slot back.
void RtspServer::Impl::close_idle_clients() {
  // Threads of medias that ended (GStreamer's task pool, GLib's shared pool) would idle
  // for 15 s each: after a burst of clients, hundreds. Let them go now.
  g_thread_pool_stop_unused_threads();
  gst_rtsp_server_client_filter(
      server,
      [](GstRTSPServer*, GstRTSPClient* client, gpointer data) {
        const auto& m = *static_cast<const Impl*>(data);
        ClientState* state = client_state(client);
        if (state == nullptr) return GST_RTSP_FILTER_KEEP;
        bool playing = false;
        if (state->played) gst_rtsp_client_session_filter(client, find_playing_session, &playing);
        const auto now = std::chrono::steady_clock::now();
        if (playing) state->idle_since = now;
        if (now - state->idle_since <= std::chrono::seconds(m.config.idle_timeout_s)) return GST_RTSP_FILTER_KEEP;
        // The socket is shut down, and the library closes the connection as when a peer
        // leaves: its read (or a TLS handshake's, blocked in a GLib worker thread) fails.
        // Closing it here instead ended the connection under a pending handshake, whose
        // task then kept the TLS connection alive for good (2.3 MB each: GnuTLS loads the
        // system's trust store per connection), and left the socket in CLOSE-WAIT.
        if (!state->shut_down) {
          state->shut_down = now;
          state->slot.reset();  // the connection is over for its client now: its slot is free for the next
          if (GstRTSPConnection* conn = gst_rtsp_client_get_connection(client)) {
            if (GSocket* socket = gst_rtsp_connection_get_read_socket(conn)) g_socket_shutdown(socket, TRUE, TRUE, nullptr);
          }
          return GST_RTSP_FILTER_KEEP;
        }
        // The next sweep: a handshake woken by the shutdown has failed by now, so removing
        // the client no longer strands it (the library does not always let go by itself).
        if (now - *state->shut_down < std::chrono::milliseconds(kIdleSweepMs / 2)) return GST_RTSP_FILTER_KEEP;
        if (GstRTSPConnection* conn = gst_rtsp_client_get_connection(client)) {
          if (GSocket* socket = gst_rtsp_connection_get_read_socket(conn)) g_socket_close(socket, nullptr);
        }
        return GST_RTSP_FILTER_REMOVE;
      },
      this);
}

void RtspServer::Impl::mount(const std::string& view) {
  GstRTSPMediaFactory* factory = gst_rtsp_media_factory_new();
  gst_rtsp_media_factory_set_launch(factory, kLaunch);
  gst_rtsp_media_factory_set_shared(factory, FALSE);  // one media per client; the encoder is shared below it
  gst_rtsp_media_factory_set_latency(factory, 0);
  auto* ctx = new MountContext{&pipeline, view, key, rate_hz};
  g_signal_connect_data(
      factory, "media-configure", G_CALLBACK(on_media_configure), ctx,
      [](gpointer data, GClosure*) { delete static_cast<MountContext*>(data); }, GConnectFlags(0));
  gst_rtsp_media_factory_add_role(factory, kRole, GST_RTSP_PERM_MEDIA_FACTORY_ACCESS, G_TYPE_BOOLEAN, TRUE,
                                  GST_RTSP_PERM_MEDIA_FACTORY_CONSTRUCT, G_TYPE_BOOLEAN, TRUE, nullptr);
  gst_rtsp_mount_points_add_factory(mounts, ("/" + view).c_str(), factory);  // takes the factory
}

// Views follow the API: created ones are mounted, deleted (or renamed) ones unmounted.
// A view H.264 cannot carry (beyond its largest picture) is not mounted: its DESCRIBE gets 404 at once.
// Mounted, its media would wait for a first frame that never comes, on the one thread
// that serves every RTSP client, and stall them all for 20 s (issue 29).
void RtspServer::Impl::sync_mounts() {
  std::set<std::string> views;
  for (const auto& v : pipeline.list_views()) {
    const std::string& name = v.spec().name();
    video::H264Settings settings;
    settings.width = v.spec().width();
    settings.height = v.spec().height();
    try {
      video::check(settings);
      views.insert(name);
      unservable.erase(name);
    } catch (const std::invalid_argument& e) {
      if (unservable.insert(name).second) {
        std::cerr << "omniviewd: rtsp: view '" << name << "' is not served: " << e.what() << std::endl;
      }
    }
  }
  std::lock_guard lock(mutex);
  for (const auto& v : views) {
    if (!mounted.count(v)) mount(v);
  }
  for (const auto& v : mounted) {
    if (!views.count(v)) gst_rtsp_mount_points_remove_factory(mounts, ("/" + v).c_str());
  }
  mounted = std::move(views);
  // Sessions whose client vanished without TEARDOWN end after their timeout.
  GstRTSPSessionPool* pool = gst_rtsp_server_get_session_pool(server);
  gst_rtsp_session_pool_cleanup(pool);
  g_object_unref(pool);
}

RtspServer::RtspServer(const DaemonConfig& config, Pipeline& pipeline) : impl_(std::make_unique<Impl>(pipeline)) {
  init_gstreamer();
  Impl& m = *impl_;
  m.config = *config.rtsp;
  m.key = encoding_key(v1::H264, m.config.quality, false, m.config.max_bitrate_kbps);
  m.rate_hz = m.config.max_rate_hz > 0 ? m.config.max_rate_hz : config.limits.max_rate_hz;
  const auto hp = split_host_port(m.config.listen);
  if (!hp) throw std::runtime_error("rtsp.listen: expected host:port, got '" + m.config.listen + "'");

  m.server = gst_rtsp_server_new();
  gst_rtsp_server_set_address(m.server, hp->host.c_str());
  gst_rtsp_server_set_service(m.server, hp->port.c_str());
  // The library's listen queue is 5 deep: a burst of players (or a scan) beyond it waits a
  // whole SYN retry (1 s) per connection. The caps below, not the queue, bound clients.
  gst_rtsp_server_set_backlog(m.server, 128);
  GstRTSPSessionPool* pool = gst_rtsp_server_get_session_pool(m.server);
  gst_rtsp_session_pool_set_max_sessions(pool, static_cast<guint>(config.limits.max_streams));
  g_object_unref(pool);
  // Clients are served on the server's own thread, not on the library's client threads:
  // such a thread stops when its last client leaves, and a TLS handshake's completion
  // queued on its GMainContext (GTlsConnection runs the handshake as a GTask that returns
  // there) then never runs, so each RTSPS connection's TLS stream, socket and GnuTLS
  // session were kept for good (a socket in CLOSE-WAIT and ~3.7 MB per connection). The
  // library's default is one such thread for all clients anyway.
  GstRTSPThreadPool* threads = gst_rtsp_server_get_thread_pool(m.server);
  gst_rtsp_thread_pool_set_max_threads(threads, 0);
  g_object_unref(threads);
  m.limits = std::make_shared<ConnectionLimits>(m.config.max_connections, m.config.max_connections_per_client);
  g_signal_connect(m.server, "client-connected", G_CALLBACK(+[](GstRTSPServer*, GstRTSPClient* client, gpointer data) {
                     static_cast<Impl*>(data)->connected(client);
                   }),
                   &m);

  // Who may watch: the API's tokens (either role) as the basic-auth password; without
  // tokens, everybody. TLS (RTSPS) with the API's certificate. Every request is checked
  // (rtsp_auth.h), and every new connection against the caps.
  m.auth = make_rtsp_auth({[&m](GstRTSPContext* ctx) { return m.admit(ctx); },
                           [&m](GstRTSPContext* ctx) { m.unauthorized(ctx); }, foreign_session,
                           [&m](GstRTSPContext* ctx) { m.untie_foreign_session(ctx); }});
  for (const auto& t : config.tokens) {
    gchar* basic = gst_rtsp_auth_make_basic(kUser, t.token.c_str());
    GstRTSPToken* token = gst_rtsp_token_new(GST_RTSP_TOKEN_MEDIA_FACTORY_ROLE, G_TYPE_STRING, kRole, nullptr);
    gst_rtsp_auth_add_basic(m.auth, basic, token);
    gst_rtsp_token_unref(token);
    g_free(basic);
  }
  if (config.tokens.empty()) {
    GstRTSPToken* anyone = gst_rtsp_token_new(GST_RTSP_TOKEN_MEDIA_FACTORY_ROLE, G_TYPE_STRING, kRole, nullptr);
    gst_rtsp_auth_set_default_token(m.auth, anyone);
    gst_rtsp_token_unref(anyone);
  }
  if (config.tls) {
    GError* e = nullptr;
    GTlsCertificate* cert =
        g_tls_certificate_new_from_files(config.tls->cert_file.c_str(), config.tls->key_file.c_str(), &e);
    if (cert == nullptr) {
      const std::string why = e ? e->message : "unknown error";
      if (e) g_error_free(e);
      throw std::runtime_error("rtsp: cannot load the TLS certificate: " + why);
    }
    gst_rtsp_auth_set_tls_certificate(m.auth, cert);
    g_object_unref(cert);
    // GLib's TLS (GStreamer's RTSPS, nothing else in the daemon: gRPC and the web port use
    // OpenSSL) builds each connection's credentials from its default database, which is
    // the system's trust store: ~140 CAs parsed per connection (2.3 MB, ~0.1 s under ASan).
    // A server that asks for no client certificate trusts nobody anyway, so the default
    // becomes the few certificates of our own files: the client CA if mutual TLS is on, else
    // our certificate's chain.
    {
      const std::string anchors =
          config.tls->client_ca_file.empty() ? config.tls->cert_file : config.tls->client_ca_file;
      if (GTlsDatabase* own = g_tls_file_database_new(anchors.c_str(), nullptr)) {
        g_tls_backend_set_default_database(g_tls_backend_get_default(), own);
        g_object_unref(own);
      }
    }
    if (!config.tls->client_ca_file.empty()) {
      GTlsDatabase* db = g_tls_file_database_new(config.tls->client_ca_file.c_str(), &e);
      if (db == nullptr) {
        const std::string why = e ? e->message : "unknown error";
        if (e) g_error_free(e);
        throw std::runtime_error("rtsp: cannot load tls.client_ca: " + why);
      }
      gst_rtsp_auth_set_tls_database(m.auth, db);
      gst_rtsp_auth_set_tls_authentication_mode(m.auth, G_TLS_AUTHENTICATION_REQUIRED);
      g_object_unref(db);
    }
    m.scheme = "rtsps";
  }
  gst_rtsp_server_set_auth(m.server, m.auth);

  m.mounts = gst_rtsp_server_get_mount_points(m.server);
  m.sync_mounts();
  m.context = g_main_context_new();
  m.loop = g_main_loop_new(m.context, FALSE);
  m.attach_id = gst_rtsp_server_attach(m.server, m.context);
  if (m.attach_id == 0) {
    stop();
    throw std::runtime_error("cannot listen on rtsp.listen '" + m.config.listen +
                             "' (address in use, or not an address of this machine?)");
  }
  m.port = gst_rtsp_server_get_bound_port(m.server);
  GSource* timer = g_timeout_source_new(kMountSyncMs);
  g_source_set_callback(
      timer,
      [](gpointer data) -> gboolean {
        static_cast<Impl*>(data)->sync_mounts();
        return G_SOURCE_CONTINUE;
      },
      &m, nullptr);
  g_source_attach(timer, m.context);
  g_source_unref(timer);
  GSource* sweep = g_timeout_source_new(kIdleSweepMs);
  g_source_set_callback(
      sweep,
      [](gpointer data) -> gboolean {
        static_cast<Impl*>(data)->close_idle_clients();
        return G_SOURCE_CONTINUE;
      },
      &m, nullptr);
  g_source_attach(sweep, m.context);
  g_source_unref(sweep);
  m.thread = std::thread([&m] {
    pthread_setname_np(pthread_self(), "rtsp");
    g_main_context_push_thread_default(m.context);
    g_main_loop_run(m.loop);
    g_main_context_pop_thread_default(m.context);
  });
}

RtspServer::~RtspServer() { stop(); }

std::string RtspServer::base_url() const {
  return impl_->scheme + "://" + url_host(impl_->config.listen) + ":" + std::to_string(impl_->port);
}

std::vector<std::string> RtspServer::urls() const {
  std::vector<std::string> out;
  std::lock_guard lock(impl_->mutex);
  for (const auto& v : impl_->mounted) out.push_back(base_url() + "/" + v);
  return out;
}

void RtspServer::stop() {
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.mutex);
    if (m.stopped) return;
    m.stopped = true;
  }
  if (m.server != nullptr) {
    // Every client's connection closed: their medias go, and with them their feeds.
    gst_rtsp_server_client_filter(
        m.server, [](GstRTSPServer*, GstRTSPClient*, gpointer) { return GST_RTSP_FILTER_REMOVE; }, nullptr);
  }
  if (m.loop != nullptr) {
    g_main_loop_quit(m.loop);
    if (m.thread.joinable()) m.thread.join();
  }
  if (m.context != nullptr) {
    // The listening socket's source, and any left: nothing runs on the context any more.
    if (m.attach_id != 0) {
      if (GSource* s = g_main_context_find_source_by_id(m.context, m.attach_id)) g_source_destroy(s);
    }
    while (g_main_context_pending(m.context)) g_main_context_iteration(m.context, FALSE);
  }
  if (m.mounts != nullptr) g_object_unref(m.mounts);
  if (m.auth != nullptr) g_object_unref(m.auth);
  if (m.server != nullptr) g_object_unref(m.server);
  if (m.loop != nullptr) g_main_loop_unref(m.loop);
  if (m.context != nullptr) g_main_context_unref(m.context);
  m.mounts = nullptr;
  m.auth = nullptr;
  m.server = nullptr;
  m.loop = nullptr;
  m.context = nullptr;
}

}  // namespace omniview
