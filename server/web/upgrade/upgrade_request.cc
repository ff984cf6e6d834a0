#include "server/web/upgrade/upgrade_request.h"

#include "server/auth/authenticator.h"

namespace omniview::web {

namespace http = boost::beast::http;

namespace {

std::string trim(std::string s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

int hex(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::optional<std::string> query_value(const std::string& target, const std::string& key) {
  auto values = query_values(target, key);
  if (values.empty()) return std::nullopt;
  return std::move(values.front());
}

std::vector<std::string> query_values(const std::string& target, const std::string& key) {
  std::vector<std::string> values;
  const auto q = target.find('?');
  if (q == std::string::npos) return values;
  const std::string query = target.substr(q + 1, target.find('#', q) - q - 1);
  size_t start = 0;
  while (start <= query.size()) {
    const size_t end = std::min(query.find('&', start), query.size());
    const std::string part = query.substr(start, end - start);
    const auto eq = part.find('=');
    if (part.substr(0, eq) == key && eq != std::string::npos) {
      std::string out;
      const std::string raw = part.substr(eq + 1);
      for (size_t i = 0; i < raw.size(); ++i) {
        if (raw[i] == '+') {
          out += ' ';
        } else if (raw[i] == '%' && i + 2 < raw.size() + 0 && hex(raw[i + 1]) >= 0 && hex(raw[i + 2]) >= 0) {
          out += static_cast<char>(hex(raw[i + 1]) * 16 + hex(raw[i + 2]));
          i += 2;
        } else {
          out += raw[i];
        }
      }
      values.push_back(std::move(out));
    }
    start = end + 1;
  }
  return values;
}

UpgradeRequest parse_upgrade(const http::request<http::string_body>& request) {
  UpgradeRequest up;
  up.offered = std::string(request[http::field::sec_websocket_protocol]);
  if (trim(up.offered).empty()) {
    up.protocol = WsProtocol::kConsole;
  } else {
    size_t start = 0;
    while (start <= up.offered.size() && up.protocol == WsProtocol::kNone) {
      const size_t end = std::min(up.offered.find(',', start), up.offered.size());
      const std::string p = trim(up.offered.substr(start, end - start));
      if (p == "omniview.console.v1") up.protocol = WsProtocol::kConsole;
      if (p == "foxglove.sdk.v1" || p == "foxglove.websocket.v1") up.protocol = WsProtocol::kFoxglove;
      if (up.protocol != WsProtocol::kNone) up.answer = p;
      start = end + 1;
    }
  }
  // Every Authorization header and every `token=` of the query: a wrong one anywhere is
  // refused, whatever comes before it.
  const auto [first, last] = request.equal_range(http::field::authorization);
  for (auto auth = first; auth != last; ++auth) {
    const auto value = auth->value();
    const auto token = bearer_token(std::string_view(value.data(), value.size()));
    up.tokens.push_back(token ? std::string(*token) : "");  // malformed: refused as such, never "no token"
  }
  for (auto& token : query_values(std::string(request.target()), "token")) up.tokens.push_back(std::move(token));
  return up;
}

}  // namespace omniview::web
