// What the pipeline says of itself (GetStatus, the console's status line, RTSP's "no images
// yet" answer), in the engine's own types: each front end turns it into its own message
// (server/api/status_message.h for the gRPC API).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace omniview {

struct SourceReport {
  std::string name, type;
  bool connected = false;
  double rate_hz = 0;            // frame sets per second, recent; 0 once frames stop
  double last_frame_age_s = -1;  // -1: none yet
  uint64_t frames = 0, errors = 0, dropped = 0;
  std::string message;           // its last problem
  std::vector<std::string> active_cameras;  // the cameras some watched view (or a cloud, a tap) needs
  double failure_rate = 0;       // of the recent image requests (0..1)
  bool degraded = false;         // connected, but failure_rate is high: fewer frames than asked
};

// A view with depth MEASURED: its geometry and updates (pipeline_depth.cc).
struct DepthReport {
  double geometry_age_s = -1;  // -1: none yet
  double update_ms = 0;        // the last update
  uint64_t updates = 0;
  double measured_fraction = 0;  // of the view's pixels
  std::string message;           // why there is no measured depth, when there is none
};

struct ViewReport {
  std::string name;
  uint32_t subscribers = 0;
  double fps = 0;  // recent; 0 once frames stop
  uint64_t frames = 0, map_rebuilds = 0;
  double last_map_build_ms = 0, coverage = 0, last_latency_ms = 0;
  bool map_pending = false;  // the source's cameras changed and the map is being rebuilt
  std::optional<DepthReport> depth;
};

// One client of a view (any front end) or of a source's cloud ("cloud:SOURCE").
struct ClientReport {
  std::string peer, view;
  uint64_t frames_sent = 0, frames_dropped = 0;
  std::string encoding;
};

struct PipelineReport {
  double uptime_s = 0;
  std::vector<SourceReport> sources;
  std::vector<ViewReport> views;
  std::vector<ClientReport> clients;
};

}  // namespace omniview
