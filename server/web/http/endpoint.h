// What an HTTP connection asks of the web server: the static files, and whether (and with
// which protocol) a WebSocket upgrade is accepted. Non-template, so the transport-specific
// sessions stay thin.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <boost/beast/http.hpp>

#include "server/web/http/static_files.h"
#include "server/web/ws/ws_session.h"

namespace omniview::web {

using Request = beast::http::request<beast::http::string_body>;

struct UpgradeDecision {
  int status = 101;         // 101: accept; else the HTTP status refusing it (400, 401, 403, 503)
  std::string message;      // the refusal, for a person
  std::string subprotocol;  // answered in Sec-WebSocket-Protocol
  ProtocolFactory make;
};

// A reply to a plain HTTP route (WHEP): status, type, body and extra headers.
struct RouteReply {
  int status = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
};

class Endpoint {
 public:
  virtual ~Endpoint() = default;
  // Routes other than the files and upgrades (WHEP's /whep/...): false when `request` is
  // not one of them; else the reply comes through `done`, later and on any thread (the
  // work may block, so it runs off the I/O thread).
  virtual bool route(const Request& request, const std::string& peer, std::function<void(RouteReply)> done) = 0;
  virtual UpgradeDecision upgrade(const Request& request, const std::string& peer) = 0;
  virtual const StaticFiles& files() const = 0;
  virtual WsLimits ws_limits() const = 0;
};

}  // namespace omniview::web
