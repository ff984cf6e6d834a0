// What every web client's protocol shares, owned by the WebServer.
#pragma once

#include <functional>
#include <string>

#include <boost/asio/thread_pool.hpp>

#include "server/auth/authenticator.h"
#include "server/config/daemon_config.h"
#include "server/pipeline/pipeline.h"
#include "server/status/failure.h"
#include "server/web/console/api_calls.h"

namespace omniview::web {

struct WebContext {
  Pipeline& pipeline;
  const Authenticator& auth;
  const ApiCalls& calls;
  const Limits& limits;                 // the API's limits: rates, streams per client
  boost::asio::thread_pool& workers;    // runs calls that may block (a view's map rebuilt)
  // Logs a refused token or call, at most a few lines per peer host every 10 s.
  std::function<void(const std::string& peer, const std::string& why)> refused;
  // Logs a connection that authenticated: peer, protocol and the token's label (never the token).
  std::function<void(const std::string& peer, const std::string& protocol, const Caller& caller)> authenticated;
};

}  // namespace omniview::web
