// What a WebSocket upgrade request asks for: which protocol (by the subprotocols offered)
// and which token (Authorization header, or `token` in the query for clients that cannot
// set headers, such as Foxglove's).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <boost/beast/http.hpp>

namespace omniview::web {

enum class WsProtocol { kNone, kConsole, kFoxglove };

struct UpgradeRequest {
  WsProtocol protocol = WsProtocol::kNone;
  std::string answer;   // the subprotocol to answer with: the client's own spelling; "" if none offered
  std::string offered;  // what the client offered, for messages
  // Every token the request carries: the Authorization headers', then the query's. Each must
  // be valid (a wrong one is a 401 even beside a good one: never silently ignored); the
  // first decides the caller. A malformed header counts as a token "" (refused as such).
  std::vector<std::string> tokens;
};

// No subprotocol offered means the console. Of several, the first one served here wins.
UpgradeRequest parse_upgrade(const boost::beast::http::request<boost::beast::http::string_body>& request);

// `key`'s value in the query of `target` ("/?token=abc%2B"), percent-decoded; the first
// if it appears more than once.
std::optional<std::string> query_value(const std::string& target, const std::string& key);
// Every value of `key` in the query, in order, percent-decoded.
std::vector<std::string> query_values(const std::string& target, const std::string& key);

}  // namespace omniview::web
