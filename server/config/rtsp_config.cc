// `rtsp:` — the RTSP server's address and the H.264 its clients get.
#include <string>

#include "server/config/config_parts.h"
#include "server/exposure/host_port.h"

namespace omniview::config_parts {

RtspConfig parse_rtsp(const YamlReader& r, const YAML::Node& n, const Limits& limits) {
  RtspConfig rtsp;
  if (!n.IsMap()) r.fail(n, "rtsp", "expected a map: {listen: 127.0.0.1:8554} (other keys optional)");
  r.expect_keys(n, "rtsp", {"listen", "quality", "max_bitrate_kbps", "max_rate_hz"});
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
  return rtsp;
}

}  // namespace omniview::config_parts
