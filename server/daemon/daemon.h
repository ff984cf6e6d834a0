// omniviewd assembled: sources from the config, the pipeline, the views, the gRPC server
// (with health and reflection), and an orderly shutdown.
#pragma once

#include <memory>
#include <string>

#include <grpcpp/server.h>

#include "server/api/omniview_service.h"
#include "server/auth/authenticator.h"
#include "server/blackbox/black_box.h"
#include "server/config/daemon_config.h"
#include "server/pipeline/pipeline.h"
#include "server/rtsp/rtsp_server.h"

namespace omniview {

namespace web {
class WebServer;
}

class Daemon {
 public:
  // Creates the sources, the configured views and the TLS credentials, and starts
  // listening. Throws ConfigError naming the file, line and key for anything the config
  // asks that cannot be done (a source that cannot start, a view its rig cannot serve, an
  // address in use). With `listen` false (omniviewd --check) it stops before listening:
  // everything that could fail at start but the address has then been tried.
  explicit Daemon(const DaemonConfig& config, bool listen = true);
  ~Daemon();

  // The address actually listened on (a config port of 0 picks a free one: tests).
  const std::string& address() const { return address_; }
  // The web endpoint's console URL ("http://127.0.0.1:8765/"); empty when `web` is off.
  std::string web_url() const;
  std::string whep_summary() const;  // WebServer::whep_summary, empty without a web port
  // Its host:port; empty when off.
  std::string web_address() const;
  Pipeline& pipeline() { return *pipeline_; }
  // With an `rtsp:` block: each view's rtsp:// URL now (empty without).
  std::vector<std::string> rtsp_urls() const;

  // Ends streams with UNAVAILABLE "omniviewd is shutting down", stops accepting calls,
  // waits up to `grace` for calls in flight, stops the sources. Idempotent.
  void shutdown(std::chrono::milliseconds grace = std::chrono::milliseconds(2000));

 private:
  DaemonConfig config_;
  std::unique_ptr<Pipeline> pipeline_;
  std::unique_ptr<BlackBox> black_box_;  // after the pipeline: stopped and destroyed before it
  std::unique_ptr<Authenticator> auth_;
  std::unique_ptr<OmniviewService> service_;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<RtspServer> rtsp_;
  std::unique_ptr<web::WebServer> web_;  // after the pipeline and auth: destroyed before them
  std::string address_;
  bool shut_down_ = false;
};

}  // namespace omniview
