#include "server/web/web_server.h"

#include <filesystem>
#include <iostream>

#include <boost/asio/strand.hpp>

#include "server/auth/permissions.h"
#include "server/exposure/host_port.h"
#include "server/web/console/console_protocol.h"
#include "server/web/foxglove/foxglove_protocol.h"
#include "server/web/http/http_session.h"
#include "server/web/upgrade/upgrade_request.h"

namespace omniview::web {

namespace fs = std::filesystem;

namespace {

// The console's files: the config's folder, else the installed copy beside the program
// (PREFIX/bin/omniviewd -> PREFIX/share/omniview/console), else the source tree's (a build).
std::string find_console_dir(const WebConfig& web) {
  if (!web.console_dir.empty()) return web.console_dir;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "omniview" / "console";
    if (fs::is_regular_file(installed / "index.html", ec)) return installed.string();
  }
#ifdef OMNIVIEW_CONSOLE_SOURCE_DIR
  if (fs::is_regular_file(fs::path(OMNIVIEW_CONSOLE_SOURCE_DIR) / "index.html", ec)) return OMNIVIEW_CONSOLE_SOURCE_DIR;
#endif
  return "";
}

std::string peer_name(const net::ip::tcp::endpoint& e) {
  const auto a = e.address();
  return a.is_v4() ? "ipv4:" + a.to_string() + ":" + std::to_string(e.port())
                   : "ipv6:[" + a.to_string() + "]:" + std::to_string(e.port());
}

[[noreturn]] void fail_listen(const DaemonConfig& config, const std::string& why) {
  const WebConfig& web = config.web;
  if (config.reader && web.listen_node) config.reader->fail(web.listen_node, "web.listen", why);
  throw ConfigError(config.file + ": web.listen: " + why);
}

}  // namespace

WebServer::WebServer(const DaemonConfig& config, Pipeline& pipeline, const Authenticator& auth)
    : config_(config.web),
      limits_(config.limits),
      tls_(config.tls.has_value()),
      auth_(auth),
      calls_(pipeline, limits_),
      context_{pipeline, auth, calls_, limits_, workers_,
               [this](const std::string& peer, const std::string& why) { log_refusal(peer, why); },
               [](const std::string& peer, const std::string& protocol, const Caller& caller) {
                 std::cerr << "omniviewd: web: " << peer << " (" << protocol << ") authenticated with "
                           << caller.label << " (" << to_string(caller.role) << ")" << std::endl;
               }} {
  if (config_.webrtc.enabled) {
    whep_ = std::make_unique<webrtc::WhepServer>(config_.webrtc, limits_, pipeline);
    const auto& rtc = config_.webrtc;
    const int ports = rtc.min_udp_port ? rtc.max_udp_port - rtc.min_udp_port + 1 : 0;
    if (ports && ports < std::min(rtc.max_sessions, limits_.max_streams)) {
      // Each viewer holds a port of the range: viewers past it are refused (503).
      std::cerr << "omniviewd: web: warning: web.webrtc.udp_ports holds " << ports << " ports, fewer than the "
                << std::min(rtc.max_sessions, limits_.max_streams)
                << " WebRTC viewers web.webrtc.max_sessions allows: viewers past " << ports << " will be refused"
                << std::endl;
    }
    if (!whep_->unavailable().empty()) {
      std::cerr << "omniviewd: web: WebRTC (WHEP) is off: " << whep_->unavailable() << std::endl;
    }
  }
  ws_limits_.max_message_bytes = static_cast<size_t>(config_.max_message_bytes);
  ws_limits_.max_pending_bytes = static_cast<size_t>(config_.max_pending_bytes);
  console_dir_ = find_console_dir(config_);
  if (console_dir_.empty()) {
    // The WebSocket protocols still work (Foxglove needs no files); say why pages are 404.
    std::cerr << "omniviewd: web: no console files found beside the program or in the source tree; "
                 "set web.console_dir to the console/ folder"
              << std::endl;
  }
  files_ = std::make_unique<StaticFiles>(std::vector<std::pair<std::string, std::string>>{
      {"/", console_dir_}, {"/javascript/", config_.javascript_dir}});

  if (tls_) {
    // The gRPC port's certificate and key (and client CA: mutual TLS) for the same clients.
    ssl_.emplace(net::ssl::context::tls_server);
    ssl_->set_options(net::ssl::context::default_workarounds | net::ssl::context::no_sslv2 |
                      net::ssl::context::no_sslv3 | net::ssl::context::no_tlsv1 | net::ssl::context::no_tlsv1_1);
    ssl_->use_certificate_chain_file(config.tls->cert_file);
    ssl_->use_private_key_file(config.tls->key_file, net::ssl::context::pem);
    if (!config.tls->client_ca_file.empty()) {
      ssl_->load_verify_file(config.tls->client_ca_file);
      ssl_->set_verify_mode(net::ssl::verify_peer | net::ssl::verify_fail_if_no_peer_cert);
    }
  }

  const auto hp = split_host_port(config_.listen);
  if (!hp) fail_listen(config, "'" + config_.listen + "' is not host:port");
  boost::system::error_code ec;
  net::ip::tcp::resolver resolver(ioc_);
  const auto results = resolver.resolve(hp->host, hp->port, net::ip::tcp::resolver::passive, ec);
  if (ec || results.empty()) fail_listen(config, "cannot resolve '" + hp->host + "': " + ec.message());
  const net::ip::tcp::endpoint endpoint = results.begin()->endpoint();
  acceptor_.open(endpoint.protocol(), ec);
  if (!ec) acceptor_.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) acceptor_.bind(endpoint, ec);
  if (!ec) acceptor_.listen(net::socket_base::max_listen_connections, ec);
  if (ec) fail_listen(config, "cannot listen on '" + config_.listen + "': " + ec.message());
  const auto bound = acceptor_.local_endpoint();
  address_ = (bound.address().is_v6() ? "[" + bound.address().to_string() + "]" : bound.address().to_string()) + ":" +
             std::to_string(bound.port());
  accept();
  // One thread moves the bytes (TLS included); calls that may block run on workers_.
  threads_.emplace_back([this] { run_io(); });
}

WebServer::~WebServer() { stop(); }

// Sessions catch what their handlers throw (a 500, a close with 1011); this is the net
// under that net: an exception out of any other handler is logged and the loop goes on,
// as Asio's documentation advises, instead of ending the thread and with it the daemon.
void WebServer::run_io() {
  for (;;) {
    try {
      ioc_.run();
      return;
    } catch (const std::exception& e) {
      std::cerr << "omniviewd: web: internal error in the I/O loop: " << e.what() << std::endl;
    } catch (...) {
      std::cerr << "omniviewd: web: internal error in the I/O loop (an exception of unknown type)" << std::endl;
    }
  }
}

std::string WebServer::url() const { return std::string(tls_ ? "https://" : "http://") + address_ + "/"; }

void WebServer::accept() {
  acceptor_.async_accept(net::make_strand(ioc_), beast::bind_front_handler(&WebServer::on_accept, this));
}

std::shared_ptr<void> WebServer::take_slot() {
  if (connections_.fetch_add(1) >= config_.max_connections) {
    --connections_;
    return nullptr;
  }
  // Non-null (the server itself; never deleted): an empty slot means "refused".
  return std::shared_ptr<void>(static_cast<void*>(this), [this](void*) { --connections_; });
}

void WebServer::on_accept(beast::error_code ec, net::ip::tcp::socket socket) {
  if (ec == net::error::operation_aborted || !acceptor_.is_open()) return;
  if (!ec) {
    boost::system::error_code peer_ec;
    const std::string peer = peer_name(socket.remote_endpoint(peer_ec));
    auto slot = take_slot();
    if (!slot) {
      log_refusal(peer, "web.max_connections (" + std::to_string(config_.max_connections) + ") reached");
      socket.close(peer_ec);
    } else if (ssl_) {
      auto stream = std::make_shared<beast::ssl_stream<beast::tcp_stream>>(std::move(socket), *ssl_);
      beast::get_lowest_layer(*stream).expires_after(std::chrono::seconds(10));
      stream->async_handshake(net::ssl::stream_base::server, [this, stream, peer, slot](beast::error_code hs) {
        if (hs) return;  // not TLS (plaintext to a TLS port), or a certificate refused
        std::make_shared<HttpSession<beast::ssl_stream<beast::tcp_stream>>>(std::move(*stream), peer, *this, slot)
            ->run();
      });
    } else {
      std::make_shared<HttpSession<beast::tcp_stream>>(beast::tcp_stream(std::move(socket)), peer, *this, slot)->run();
    }
  }
  accept();
}

UpgradeDecision WebServer::upgrade(const Request& request, const std::string& peer) {
  UpgradeRequest up = parse_upgrade(request);
  UpgradeDecision d;
  if (up.protocol == WsProtocol::kNone) {
    d.status = 400;
    d.message = "none of the WebSocket subprotocols offered (" + up.offered +
                ") is served here: use omniview.console.v1, foxglove.sdk.v1 or foxglove.websocket.v1";
    return d;
  }
  std::optional<Caller> caller;
  for (const std::string& token : up.tokens) {  // every one given must be valid; the first decides
    Caller who;
    const grpc::Status s = auth_.check_header("Bearer " + token, Role::kViewer, &who);
    if (!s.ok()) {
      log_refusal(peer, s.error_message());
      d.status = 401;
      d.message = s.error_message();
      // A '+' left as it is in a URL's query reads as a space: say how to write the token.
      if (token.find(' ') != std::string::npos) {
        d.message = "the token in the URL (?token=) has a space where it had a '+': percent-encode the token in "
                    "a URL (+ as %2B, / as %2F, = as %3D), or send it in an 'Authorization: Bearer' header";
      }
      return d;
    }
    if (!caller) caller = who;
  }
  if (caller) {
    if (auth_.enabled()) context_.authenticated(peer, up.answer.empty() ? kConsoleSubprotocol : up.answer, *caller);
  } else if (!auth_.enabled()) {
    caller = Caller{Role::kOperator, ""};
  }
  d.subprotocol = up.answer;
  if (up.protocol == WsProtocol::kConsole) {
    d.make = [this, caller](std::shared_ptr<Connection> connection) -> std::unique_ptr<Protocol> {
      track(connection);
      return std::make_unique<ConsoleProtocol>(connection, context_, caller);
    };
    return d;
  }
  if (!caller) {
    d.status = 401;
    d.message = "this daemon needs a token: connect to ws://HOST:PORT/?token=TOKEN (Foxglove and Lichtblick: "
                "put it in the connection's URL), or send 'Authorization: Bearer TOKEN'";
    log_refusal(peer, "a Foxglove client without a token");
    return d;
  }
  d.make = [this, who = *caller](std::shared_ptr<Connection> connection) -> std::unique_ptr<Protocol> {
    track(connection);
    return std::make_unique<FoxgloveProtocol>(connection, context_, who);
  };
  return d;
}

std::string WebServer::whep_summary() const {
  if (!whep_) return "";
  if (!whep_->unavailable().empty()) return "off: " + whep_->unavailable();
  return "POST " + url() + "whep/VIEW (UDP media" +
         (config_.webrtc.min_udp_port ? " on ports " + std::to_string(config_.webrtc.min_udp_port) + "-" +
                                            std::to_string(config_.webrtc.max_udp_port)
                                      : std::string()) +
         ")";
}

// WHEP: POST /whep/VIEW (an offer), DELETE /whep/VIEW/ID (the session's Location), OPTIONS
// on either; PATCH (trickle ICE, ICE restart) is not served: the answer holds every
// candidate, and a viewer restarts by DELETE and a new POST.
bool WebServer::route(const Request& request, const std::string& peer, std::function<void(HttpReply)> done) {
  std::string path(request.target());
  path = path.substr(0, path.find('?'));
  if (path != "/whep" && path.rfind("/whep/", 0) != 0) return false;
  const std::string rest = path.size() > 6 ? path.substr(6) : "";
  const auto slash = rest.find('/');
  const std::string view = rest.substr(0, slash), id = slash == std::string::npos ? "" : rest.substr(slash + 1);
  const auto reply = [&](int status, std::string text, std::vector<std::pair<std::string, std::string>> headers = {}) {
    HttpReply r;
    r.status = status;
    r.body = std::move(text) + "\n";
    r.headers = std::move(headers);
    done(std::move(r));
    return true;
  };
  namespace http = beast::http;
  if (!whep_) return reply(404, "WebRTC is off on this daemon (web.webrtc.enabled: false)");
  if (view.empty() || id.find('/') != std::string::npos) {
    return reply(404, "WHEP: POST an SDP offer to /whep/VIEW (a view's name); DELETE the Location it answers");
  }
  const std::string allow = id.empty() ? "POST, OPTIONS" : "DELETE, OPTIONS";
  switch (request.method()) {
    case http::verb::options: {
      HttpReply r;
      r.status = 204;
      r.headers = {{"Allow", allow}};
      if (id.empty()) r.headers.emplace_back("Accept-Post", "application/sdp");
      // The ICE servers only to a caller who may watch: a TURN server's Link holds its
      // password (an OPTIONS without a token got it, and with it an open relay). Without a
      // valid token the answer is still 204 (a CORS preflight carries none), without Links.
      const auto header = request.find(http::field::authorization);
      std::optional<std::string_view> authorization;
      if (header != request.end()) authorization = std::string_view(header->value().data(), header->value().size());
      // To such a caller, an unknown view or session is 404 as its POST or DELETE would be
      // (not to others: view names are for those who may watch).
      Caller who;
      if (auth_.check_header(authorization, permissions::role_for("whep:POST").value_or(Role::kOperator), &who).ok()) {
        if (std::string unknown = whep_->unknown(view, id); !unknown.empty()) return reply(404, std::move(unknown));
        for (auto& link : whep_->ice_server_links()) r.headers.push_back(std::move(link));
      }
      done(std::move(r));
      return true;
    }
    case http::verb::post:
      if (!id.empty()) break;
      [[fallthrough]];
    case http::verb::delete_: {
      if (request.method() == http::verb::delete_ && id.empty()) break;
      // The same tokens as every other route, the role from the one table.
      const auto header = request.find(http::field::authorization);
      std::optional<std::string_view> authorization;
      if (header != request.end()) authorization = std::string_view(header->value().data(), header->value().size());
      const bool posting = request.method() == http::verb::post;
      const auto needed = permissions::role_for(std::string("whep:") + (posting ? "POST" : "DELETE"));
      Caller who;
      const grpc::Status s = auth_.check_header(authorization, needed.value_or(Role::kOperator), &who);
      if (!s.ok()) {
        // In HTTP's words: the authenticator's speak of gRPC metadata.
        const bool no_token = s.error_code() == grpc::StatusCode::UNAUTHENTICATED && header == request.end();
        const std::string why = no_token ? "a token is needed: send 'Authorization: Bearer TOKEN'"
                                : s.error_code() == grpc::StatusCode::UNAUTHENTICATED && s.error_message() != "unknown token"
                                    ? "malformed Authorization header: send 'Authorization: Bearer TOKEN'"
                                    : s.error_message();
        log_refusal(peer, "WHEP " + std::string(posting ? "POST" : "DELETE") + ": " + why);
        return reply(http_status(kind_of(s.error_code())), why, {{"WWW-Authenticate", "Bearer"}});
      }
      const std::string client = peer.substr(0, peer.rfind(':'));
      const auto type = request.find(http::field::content_type);
      const std::string content_type = type == request.end() ? "" : std::string(type->value());
      const bool post = request.method() == http::verb::post;
      const std::string body = post ? request.body() : "";
      // Off the I/O thread: the offer/answer and a session's end wait on GStreamer's threads.
      net::post(workers_, [this, post, view, id, content_type, body, client, peer, who, done = std::move(done)] {
        HttpReply a;
        try {
          a = post ? whep_->create(view, content_type, body, client, peer, who) : whep_->remove(view, id, peer, who);
        } catch (const std::exception& e) {
          std::cerr << "omniviewd: web: " << peer << ": WHEP: internal error: " << e.what() << std::endl;
          a.status = 500;
          a.body = "internal server error\n";
        }
        done(std::move(a));
      });
      return true;
    }
    default: break;
  }
  if (request.method() == http::verb::patch) {
    return reply(405, "trickle ICE and ICE restarts are not served: the answer holds every candidate; to restart, "
                      "DELETE the session and POST a new offer",
                 {{"Allow", allow}});
  }
  return reply(405, "WHEP here: " + allow + " on " + path, {{"Allow", allow}});
}

void WebServer::track(const std::shared_ptr<Connection>& connection) {
  std::lock_guard lock(live_mutex_);
  std::erase_if(live_, [](const auto& w) { return w.expired(); });
  live_.push_back(connection);
}

void WebServer::log_refusal(const std::string& peer, const std::string& why) {
  const auto left_out = refusals_.admit(peer);
  if (!left_out) return;
  std::cerr << "omniviewd: web: refused " << peer << ": " << why
            << (*left_out ? " (and " + std::to_string(*left_out) + " more refusals from this host not logged)" : "")
            << std::endl;
}

void WebServer::stop(std::chrono::milliseconds grace) {
  if (stopped_) return;
  stopped_ = true;
  net::post(ioc_, [this] {
    boost::system::error_code ec;
    acceptor_.close(ec);
  });
  {
    std::lock_guard lock(live_mutex_);
    for (const auto& w : live_) {
      if (const auto c = w.lock()) c->close(1001, "omniviewd is shutting down");
    }
  }
  const auto deadline = std::chrono::steady_clock::now() + grace;
  while (std::chrono::steady_clock::now() < deadline) {
    {
      std::lock_guard lock(live_mutex_);
      std::erase_if(live_, [](const auto& w) { return w.expired(); });
      if (live_.empty()) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ioc_.stop();
  for (auto& t : threads_) t.join();
  workers_.join();
}

}  // namespace omniview::web
