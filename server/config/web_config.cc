// `web:` — the HTTP + WebSocket endpoint (server/web). It has no TLS or tokens of its own:
// the gRPC API's `tls` and `tokens` apply, so a browser and a gRPC client are held to the
// same rules (docs/SECURITY.md).
#include <filesystem>
#include <sstream>
#include <string>

#include "server/config/config_parts.h"
#include "server/exposure/host_port.h"

namespace omniview::config_parts {
namespace {

int int_in(const YamlReader& r, const YAML::Node& n, const std::string& path, int lo, int hi) {
  const int v = r.integer(n, path);
  if (v < lo || v > hi) {
    r.fail(n, path, "must be from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " + std::to_string(v));
  }
  return v;
}

// `web.webrtc:` (WHEP). The ICE server URLs are checked for their scheme here, the rest of
// them by webrtcbin when a viewer comes.
WebRtcConfig parse_webrtc(const YamlReader& r, const YAML::Node& n) {
  WebRtcConfig webrtc;
  if (!n.IsDefined() || n.IsNull()) return webrtc;
  if (!n.IsMap()) r.fail(n, "web.webrtc", "expected a map {enabled, stun_server, turn_server, udp_ports, ...}");
  r.expect_keys(n, "web.webrtc", {"enabled", "stun_server", "turn_server", "udp_ports", "max_sessions",
                                  "max_sessions_per_client", "quality", "max_bitrate_kbps"});
  webrtc.enabled = n["enabled"] ? r.boolean(n["enabled"], "web.webrtc.enabled") : true;
  const auto url = [&](const char* key, std::initializer_list<const char*> schemes) {
    const YAML::Node v = n[key];
    if (!v) return std::string();
    const std::string path = std::string("web.webrtc.") + key, text = r.text(v, path);
    for (const char* scheme : schemes) {
      if (text.rfind(scheme, 0) == 0 && text.size() > std::string(scheme).size()) return text;
    }
    std::string expected;
    for (const char* scheme : schemes) expected += (expected.empty() ? "" : " or ") + std::string(scheme) + "...";
    r.fail(v, path, "expected " + expected + ", got '" + text + "'");
  };
  webrtc.stun_server = url("stun_server", {"stun://"});
  webrtc.turn_server = url("turn_server", {"turn://", "turns://"});
  if (!webrtc.turn_server.empty()) {
    // A TURN server allocates relays only for a user it knows (RFC 5766's long-term
    // credentials): without them every allocation fails, and only the log would say so.
    const std::string rest = webrtc.turn_server.substr(webrtc.turn_server.find("://") + 3);
    const auto at = rest.rfind('@');
    const std::string credentials = at == std::string::npos ? "" : rest.substr(0, at);
    const auto colon = credentials.find(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == credentials.size() || at + 1 == rest.size()) {
      r.fail(n["turn_server"], "web.webrtc.turn_server",
             "expected turn://USER:PASSWORD@HOST:PORT (a TURN server relays only for a user it knows), got '" +
                 webrtc.turn_server.substr(0, webrtc.turn_server.find("://") + 3) + (at == std::string::npos ? rest : "...@" + rest.substr(at + 1)) + "'");
    }
  }
  if (const YAML::Node ports = n["udp_ports"]) {
    const std::string text = r.text(ports, "web.webrtc.udp_ports");
    int lo = 0, hi = 0;
    char dash = 0;
    std::istringstream in(text);
    if (!(in >> lo >> dash >> hi) || dash != '-' || !in.eof() || lo < 1024 || hi > 65535 || hi < lo + 1) {
      r.fail(ports, "web.webrtc.udp_ports",
             "expected MIN-MAX with 1024 <= MIN < MAX <= 65535 (two ports or more: RTP and its ICE checks), got '" +
                 text + "'");
    }
    webrtc.min_udp_port = lo;
    webrtc.max_udp_port = hi;
  }
  if (n["max_sessions"]) webrtc.max_sessions = int_in(r, n["max_sessions"], "web.webrtc.max_sessions", 1, 1000);
  if (n["max_sessions_per_client"]) {
    webrtc.max_sessions_per_client =
        int_in(r, n["max_sessions_per_client"], "web.webrtc.max_sessions_per_client", 1, 1000);
  }
  if (n["quality"]) webrtc.quality = int_in(r, n["quality"], "web.webrtc.quality", 0, 100);
  if (n["max_bitrate_kbps"]) {
    webrtc.max_bitrate_kbps = int_in(r, n["max_bitrate_kbps"], "web.webrtc.max_bitrate_kbps", 0, 1000000);
  }
  return webrtc;
}

}  // namespace

WebConfig parse_web(const YamlReader& r, const YAML::Node& n, const std::string& folder) {
  WebConfig web;
  if (!n.IsDefined() || n.IsNull()) return web;
  if (!n.IsMap()) r.fail(n, "web", "expected a map {enabled, listen, ...}");
  r.expect_keys(n, "web", {"enabled", "listen", "console_dir", "javascript_dir", "max_connections",
                           "max_message_bytes", "max_pending_bytes", "webrtc"});
  // A `web:` block means "serve it" unless it says otherwise.
  web.enabled = n["enabled"] ? r.boolean(n["enabled"], "web.enabled") : true;
  if (const YAML::Node listen = n["listen"]) {
    web.listen = r.text(listen, "web.listen");
    web.listen_node = listen;
    if (is_unix_address(web.listen)) {
      r.fail(listen, "web.listen", "the web endpoint listens on TCP only (host:port, e.g. 127.0.0.1:8765)");
    }
    if (const auto problem = listen_address_problem(web.listen); !problem.empty()) r.fail(listen, "web.listen", problem);
  }
  for (const char* key : {"console_dir", "javascript_dir"}) {
    const YAML::Node dir = n[key];
    if (!dir) continue;
    const std::string path = std::string("web.") + key;
    const std::string value = resolve_config_path(folder, r.text(dir, path));
    std::error_code ec;
    if (!std::filesystem::is_directory(value, ec)) r.fail(dir, path, "'" + value + "' is not a folder");
    (key == std::string("console_dir") ? web.console_dir : web.javascript_dir) = value;
  }
  if (n["max_connections"]) web.max_connections = int_in(r, n["max_connections"], "web.max_connections", 1, 10000);
  if (n["max_message_bytes"]) {
    // A request or a view update always fits in 1 KiB; 16 MiB is far beyond any control message.
    web.max_message_bytes = int_in(r, n["max_message_bytes"], "web.max_message_bytes", 1024, 16 << 20);
  }
  if (n["max_pending_bytes"]) {
    web.max_pending_bytes = int_in(r, n["max_pending_bytes"], "web.max_pending_bytes", 64 << 10, 1 << 30);
  }
  web.webrtc = parse_webrtc(r, n["webrtc"]);
  return web;
}

}  // namespace omniview::config_parts
