// `limits:` — every bound the daemon enforces on what clients may ask for. Each value must
// be positive and within a range a robot's computer can actually serve, so a typo (an extra
// zero) fails at start-up instead of when a client first hits it.
#include <cstdint>
#include <string>

#include "core/view/view_spec.h"
#include "server/config/config_parts.h"

namespace omniview::config_parts {
namespace {

constexpr int64_t kMaxViewPixelsCeiling = int64_t{kMaxViewSide} * kMaxViewSide;
constexpr int kMaxViewsCeiling = 1024;
constexpr int kMaxStreamsCeiling = 10000;
constexpr int kMinMessageBytes = 64 << 10;  // a request, or a small JPEG, must always fit
constexpr double kMaxRateCeilingHz = 1000;
constexpr int kMaxRecordQueueFrameSets = 10000;
constexpr int kMaxRecordQueueMb = 65536;

int64_t integer_in(const YamlReader& r, const YAML::Node& n, const std::string& path, int64_t lo, int64_t hi) {
  const int64_t v = r.integer(n, path);
  if (v < lo || v > hi) {
    r.fail(n, path, "must be from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " + std::to_string(v));
  }
  return v;
}

}  // namespace

Limits parse_limits(const YamlReader& r, const YAML::Node& n) {
  Limits limits;
  if (!n.IsDefined() || n.IsNull()) return limits;
  r.expect_keys(n, "limits", {"max_view_pixels", "max_views", "max_streams_per_client", "max_streams",
                              "max_message_bytes", "max_rate_hz", "record_queue_frame_sets", "record_queue_mb"});
  if (n["max_view_pixels"]) {
    limits.max_view_pixels = integer_in(r, n["max_view_pixels"], "limits.max_view_pixels", 1, kMaxViewPixelsCeiling);
  }
  if (n["max_views"]) {
    limits.max_views = static_cast<int>(integer_in(r, n["max_views"], "limits.max_views", 1, kMaxViewsCeiling));
  }
  if (n["max_streams"]) {
    limits.max_streams = static_cast<int>(integer_in(r, n["max_streams"], "limits.max_streams", 1, kMaxStreamsCeiling));
  }
  if (n["max_streams_per_client"]) {
    const auto& node = n["max_streams_per_client"];
    limits.max_streams_per_client =
        static_cast<int>(integer_in(r, node, "limits.max_streams_per_client", 1, kMaxStreamsCeiling));
  }
  if (limits.max_streams_per_client > limits.max_streams) {
    const YAML::Node at = n["max_streams_per_client"] ? n["max_streams_per_client"] : n;
    r.fail(at, "limits.max_streams_per_client",
           std::to_string(limits.max_streams_per_client) + " is more than limits.max_streams (" +
               std::to_string(limits.max_streams) + ")");
  }
  if (n["max_message_bytes"]) {
    limits.max_message_bytes = static_cast<int>(
        integer_in(r, n["max_message_bytes"], "limits.max_message_bytes", kMinMessageBytes, INT32_MAX));
  }
  if (n["max_rate_hz"]) {
    const double hz = r.number(n["max_rate_hz"], "limits.max_rate_hz");
    if (!(hz > 0) || hz > kMaxRateCeilingHz) {
      r.fail(n["max_rate_hz"], "limits.max_rate_hz",
             "must be above 0 and at most " + std::to_string(static_cast<int>(kMaxRateCeilingHz)) + ", got " +
                 n["max_rate_hz"].Scalar());
    }
    limits.max_rate_hz = hz;
  }
  if (n["record_queue_frame_sets"]) {
    limits.record_queue_frame_sets = static_cast<int>(integer_in(
        r, n["record_queue_frame_sets"], "limits.record_queue_frame_sets", 1, kMaxRecordQueueFrameSets));
  }
  if (n["record_queue_mb"]) {
    limits.record_queue_mb =
        static_cast<int>(integer_in(r, n["record_queue_mb"], "limits.record_queue_mb", 1, kMaxRecordQueueMb));
  }
  return limits;
}

}  // namespace omniview::config_parts
