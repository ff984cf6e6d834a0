// `rtsp:` — the RTSP server's address and the H.264 its clients get.
#include <string>

#include "server/config/config_parts.h"
#include "server/exposure/host_port.h"

namespace omniview::config_parts {
namespace {

// Each connection may hold a media (a pipeline, its threads and ~10 files): the ceiling
// keeps the daemon within the systemd unit's LimitNOFILE (packaging/omniviewd.service.in).
constexpr int kMaxRtspConnectionsCeiling = 256;

int rtsp_int_in(const YamlReader& r, const YAML::Node& n, const std::string& path, int lo, int hi) {
  const auto v = r.integer(n, path);
  if (v < lo || v > hi) {
    r.fail(n, path, "must be from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " + std::to_string(v));
  }
  return static_cast<int>(v);
}

}  // namespace

RtspConfig parse_rtsp(const YamlReader& r, const YAML::Node& n, const Limits& limits) {
  RtspConfig rtsp;
  if (!n.IsMap()) r.fail(n, "rtsp", "expected a map: {listen: 127.0.0.1:8554} (other keys optional)");
  r.expect_keys(n, "rtsp", {"listen", "quality", "max_bitrate_kbps", "max_rate_hz", "max_connections",
                           "max_connections_per_client", "idle_timeout_s"});
  if (n["listen"]) {
    rtsp.listen = r.text(n["listen"], "rtsp.listen");
    const auto hp = split_host_port(rtsp.listen);
    if (is_unix_address(rtsp.listen) || !hp || hp->host.empty()) {
      r.fail(n["listen"], "rtsp.listen", "expected host:port (e.g. 127.0.0.1:8554; RTSP has no unix sockets)");
    }
    const std::string& port = hp->port;
    if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos ||
        std::stoi(port) > 65535) {
      r.fail(n["listen"], "rtsp.listen", "the port must be 0..65535 (0: a free one), got '" + port + "'");
    }
  }
  if (n["quality"]) {
    const auto q = r.integer(n["quality"], "rtsp.quality");
    if (q < 0 || q > 100) r.fail(n["quality"], "rtsp.quality", "must be 0..100 (0: the default 50, CRF 26)");
    rtsp.quality = static_cast<int>(q);
  }
  if (n["max_bitrate_kbps"]) {
    const auto kbps = r.integer(n["max_bitrate_kbps"], "rtsp.max_bitrate_kbps");
    if (kbps != 0 && (kbps < 50 || kbps > 100000)) {
      r.fail(n["max_bitrate_kbps"], "rtsp.max_bitrate_kbps", "must be 50..100000 kbit/s (0: no ceiling)");
    }
    rtsp.max_bitrate_kbps = static_cast<int>(kbps);
  }
  if (n["max_rate_hz"]) {
    rtsp.max_rate_hz = r.number(n["max_rate_hz"], "rtsp.max_rate_hz");
    if (!(rtsp.max_rate_hz >= 0 && rtsp.max_rate_hz <= limits.max_rate_hz)) {
      r.fail(n["max_rate_hz"], "rtsp.max_rate_hz",
             "must be 0..limits.max_rate_hz (" + std::to_string(limits.max_rate_hz) + "; 0: as the source delivers)");
    }
  }
  if (n["max_connections"]) {
    rtsp.max_connections = rtsp_int_in(r, n["max_connections"], "rtsp.max_connections", 1, kMaxRtspConnectionsCeiling);
  }
  if (n["max_connections_per_client"]) {
    rtsp.max_connections_per_client =
        rtsp_int_in(r, n["max_connections_per_client"], "rtsp.max_connections_per_client", 1, kMaxRtspConnectionsCeiling);
  }
  if (rtsp.max_connections_per_client > rtsp.max_connections) {
    const YAML::Node at = n["max_connections_per_client"] ? n["max_connections_per_client"] : n;
    r.fail(at, "rtsp.max_connections_per_client",
           std::to_string(rtsp.max_connections_per_client) + " is more than rtsp.max_connections (" +
               std::to_string(rtsp.max_connections) + ")");
  }
  if (n["idle_timeout_s"]) rtsp.idle_timeout_s = rtsp_int_in(r, n["idle_timeout_s"], "rtsp.idle_timeout_s", 1, 3600);
  return rtsp;
}

}  // namespace omniview::config_parts
