#include "server/api/status_message.h"

namespace omniview {

namespace {

void set_source(const SourceReport& in, v1::SourceStatus& out) {
  out.set_name(in.name);
  out.set_type(in.type);
  out.set_connected(in.connected);
  out.set_rate_hz(in.rate_hz);
  out.set_last_frame_age_s(in.last_frame_age_s);
  out.set_frames(in.frames);
  out.set_errors(in.errors);
  out.set_dropped(in.dropped);
  out.set_message(in.message);
  for (const auto& camera : in.active_cameras) out.add_active_cameras(camera);
  out.set_failure_rate(in.failure_rate);
  out.set_degraded(in.degraded);
}

void set_view(const ViewReport& in, v1::ViewStatus& out) {
  out.set_name(in.name);
  out.set_subscribers(in.subscribers);
  out.set_fps(in.fps);
  out.set_frames(in.frames);
  out.set_map_rebuilds(in.map_rebuilds);
  out.set_last_map_build_ms(in.last_map_build_ms);
  out.set_coverage(in.coverage);
  out.set_last_latency_ms(in.last_latency_ms);
  out.set_map_pending(in.map_pending);
  if (in.depth) {  // fixed views leave the depth fields at zero
    out.set_depth_geometry_age_s(in.depth->geometry_age_s);
    out.set_depth_update_ms(in.depth->update_ms);
    out.set_depth_updates(in.depth->updates);
    out.set_measured_depth(in.depth->measured_fraction);
    out.set_depth_message(in.depth->message);
  }
}

void set_client(const ClientReport& in, v1::ClientStatus& out) {
  out.set_peer(in.peer);
  out.set_view(in.view);
  out.set_frames_sent(in.frames_sent);
  out.set_frames_dropped(in.frames_dropped);
  out.set_encoding(in.encoding);
}

void set_ring(const BlackBoxRingReport& in, v1::BlackBoxStatus& out) {
  out.set_source(in.source);
  out.set_folder(in.folder);
  out.set_span_s(in.span_s);
  out.set_bytes(in.bytes);
  out.set_max_bytes(in.max_bytes);
  out.set_minutes(in.minutes);
  out.set_frame_sets(in.frame_sets);
  out.set_not_kept(in.not_kept);
  out.set_message(in.message);
  out.set_last_snapshot(in.last_snapshot);
}

}  // namespace

v1::Status status_message(const PipelineReport& pipeline, const std::vector<BlackBoxRingReport>& rings) {
  v1::Status status;
  status.set_version(OMNIVIEW_VERSION);  // the project version, from CMake
  status.set_uptime_s(pipeline.uptime_s);
  for (const auto& s : pipeline.sources) set_source(s, *status.add_sources());
  for (const auto& v : pipeline.views) set_view(v, *status.add_views());
  for (const auto& c : pipeline.clients) set_client(c, *status.add_clients());
  for (const auto& r : rings) set_ring(r, *status.add_blackbox());
  return status;
}

}  // namespace omniview
