// What a WebSocket upgrade request asks for: which protocol (by the subprotocols offered)
// and which token (Authorization header, or `token` in the query for clients that cannot
// set headers, such as Foxglove's).
#pragma once

#include <optional>
#include <string>

#include <boost/beast/http.hpp>

namespace omniview::web {

enum class WsProtocol { kNone, kConsole, kFoxglove };

struct UpgradeRequest {
  WsProtocol protocol = WsProtocol::kNone;
  std::string answer;   // the subprotocol to answer with: the client's own spelling; "" if none offered
  std::string offered;  // what the client offered, for messages
  std::optional<std::string> token;
};

// No subprotocol offered means the console. Of several, the first one served here wins.
UpgradeRequest parse_upgrade(const boost::beast::http::request<boost::beast::http::string_body>& request);

// `key`'s value in the query of `target` ("/?token=abc%2B"), percent-decoded.
std::optional<std::string> query_value(const std::string& target, const std::string& key);

}  // namespace omniview::web
