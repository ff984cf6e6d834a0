// omniviewd's HTTP + WebSocket endpoint (config `web:`): the operator console's files, the
// console's WebSocket protocol and the Foxglove WebSocket protocol, on one port.
//
// Built on Boost.Beast (Debian's libboost-dev): HTTP/1.1 and WebSocket (RFC 6455) on
// Boost.Asio, TLS through the same OpenSSL as the rest of the daemon, and its parsers are
// those of a library many projects harden, not ones written here. Asio's single event
// loop fits a few dozen browsers; frames and clouds reach it from the pipeline's
// latest-item slots through one pump thread per subscription (stream/pump.h), so a slow
// browser never slows the pipeline.
//
// The gRPC API's TLS certificate, tokens and roles apply here too, and the exposure rule
// (server/exposure) decides whether the address may be served as configured.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/thread_pool.hpp>

#include "server/auth/refusal_log.h"
#include "server/web/console/api_calls.h"
#include "server/web/http/endpoint.h"
#include "server/web/web_context.h"
#include "server/webrtc/whep_server.h"

namespace omniview::web {

class WebServer : public Endpoint {
 public:
  // Binds `config.web.listen` and starts serving. Throws ConfigError naming web.listen when
  // the address cannot be listened on.
  WebServer(const DaemonConfig& config, Pipeline& pipeline, const Authenticator& auth);
  ~WebServer() override;

  // "127.0.0.1:8765" (the port actually bound: 0 in the config picks one).
  const std::string& address() const { return address_; }
  // "http://127.0.0.1:8765/" ("https://" with TLS).
  std::string url() const;
  const std::string& console_dir() const { return console_dir_; }

  // Closes every connection ("omniviewd is shutting down"), waiting up to `grace` for them
  // to go, and stops. Idempotent.
  void stop(std::chrono::milliseconds grace = std::chrono::milliseconds(1000));

  // The WHEP line for the start-up log ("WebRTC (WHEP): POST https://HOST:PORT/whep/VIEW"),
  // or why WebRTC is off; empty when web.webrtc.enabled is false.
  std::string whep_summary() const;

  UpgradeDecision upgrade(const Request& request, const std::string& peer) override;
  bool route(const Request& request, const std::string& peer, std::function<void(HttpReply)> done) override;
  const StaticFiles& files() const override { return *files_; }
  WsLimits ws_limits() const override { return ws_limits_; }

 private:
  void accept();
  void run_io();  // the I/O thread's loop
  void on_accept(boost::beast::error_code ec, net::ip::tcp::socket socket);
  void log_refusal(const std::string& peer, const std::string& why);
  void track(const std::shared_ptr<Connection>& connection);  // closed at stop()
  std::shared_ptr<void> take_slot();

  const WebConfig config_;
  const Limits limits_;
  const bool tls_;
  const Authenticator& auth_;
  WsLimits ws_limits_;
  std::string console_dir_;
  std::unique_ptr<StaticFiles> files_;
  // Declared before the I/O context: connections still queued in it when it is destroyed
  // end their protocols, which use these.
  net::thread_pool workers_{2};
  ApiCalls calls_;
  WebContext context_;
  std::unique_ptr<webrtc::WhepServer> whep_;  // null with web.webrtc.enabled: false
  std::atomic<int> connections_{0};
  std::mutex live_mutex_;
  std::vector<std::weak_ptr<Connection>> live_;  // WebSocket clients, to close at stop()
  RefusalLog refusals_;
  std::optional<net::ssl::context> ssl_;
  net::io_context ioc_;
  net::ip::tcp::acceptor acceptor_{ioc_};
  std::vector<std::thread> threads_;
  std::string address_;
  bool stopped_ = false;
};

}  // namespace omniview::web
