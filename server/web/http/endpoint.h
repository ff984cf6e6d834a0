// What an HTTP connection asks of the web server: the static files, and whether (and with
// which protocol) a WebSocket upgrade is accepted. Non-template, so the transport-specific
// sessions stay thin.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <boost/beast/http.hpp>

#include "server/web/http/http_reply.h"
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

class Endpoint {
 public:
  virtual ~Endpoint() = default;
  // Routes other than the files and upgrades (WHEP's /whep/...): false when `request` is
  // not one of them; else the reply comes through `done`, later and on any thread (the
  // work may block, so it runs off the I/O thread).
  virtual bool route(const Request& request, const std::string& peer, std::function<void(HttpReply)> done) = 0;
  virtual UpgradeDecision upgrade(const Request& request, const std::string& peer) = 0;
  virtual const StaticFiles& files() const = 0;
  virtual WsLimits ws_limits() const = 0;
};

}  // namespace omniview::web
