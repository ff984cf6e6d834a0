// The pipeline's report of itself (GetStatus): sources, views, clients, the cameras being pulled.
#include "server/pipeline/pipeline.h"

#include <chrono>

#include "server/pipeline/frame_encoder.h"

namespace omniview {

namespace {

using Clock = std::chrono::steady_clock;

// One request in ten failing is more than a good link loses, and shows in the frame rate.
constexpr double kDegradedFailureRate = 0.1;

}  // namespace

SourceHealth Pipeline::source_health(const std::string& source) const { return channel(source).source().health(); }

PipelineReport Pipeline::report() const {
  PipelineReport report;
  const auto now = Clock::now();
  report.uptime_s = std::chrono::duration<double>(now - started_).count();
  for (const auto& c : channels_) {
    const auto stats = c->stats();
    const auto health = c->source().health();
    SourceReport& s = report.sources.emplace_back();
    s.name = c->source().name();
    s.type = c->source().type();
    s.connected = health.connected;
    const bool any = stats.last_arrival.time_since_epoch().count() != 0;
    s.last_frame_age_s = any ? std::chrono::duration<double>(now - stats.last_arrival).count() : -1;
    // The averaged rate means nothing once frames stop coming.
    s.rate_hz = any && s.last_frame_age_s < 2 + (stats.rate_hz > 0 ? 2 / stats.rate_hz : 0) ? stats.rate_hz : 0;
    s.frames = stats.frames;
    s.errors = health.errors;
    s.dropped = stats.dropped;
    s.message = health.message;
    s.failure_rate = health.failure_rate;
    s.degraded = health.connected && health.failure_rate >= kDegradedFailureRate;
  }
  std::vector<std::shared_ptr<LiveView>> views;
  {
    std::lock_guard lock(views_mutex_);
    for (const auto& [_, v] : views_) views.push_back(v);
  }
  for (const auto& v : views) {
    const auto state = v->state();
    const auto stats = v->stats();
    ViewReport& s = report.views.emplace_back();
    s.name = state->spec.name;
    const auto subscribers = v->subscribers();
    s.subscribers = static_cast<uint32_t>(subscribers.size());
    const bool recent = stats.last_frame.time_since_epoch().count() != 0 &&
                        std::chrono::duration<double>(now - stats.last_frame).count() < 2;
    s.fps = recent ? stats.fps : 0;
    s.frames = stats.frames;
    s.map_rebuilds = stats.map_rebuilds;
    s.last_map_build_ms = stats.last_map_build_ms;
    s.coverage = state->coverage;
    const auto current = rig(state->spec.source);
    s.map_pending = current && current != state->rig;
    s.last_latency_ms = stats.last_latency_ms;
    if (state->depth) {
      s.depth = describe_depth(*state, subscribers.size());
      s.depth->updates = stats.depth_updates;
    }
    for (const auto& sub : subscribers) {
      report.clients.push_back({sub->peer(), state->spec.name, sub->frames_sent(), sub->frames_dropped(), to_string(sub->key())});
    }
  }
  // Cloud clients, named by their source's cloud.
  for (const auto& [source, delivery] : clouds_) {
    for (const auto& sub : delivery->subscribers()) {
      report.clients.push_back({sub->peer(), "cloud:" + source, sub->clouds_sent(), sub->clouds_dropped(), "cloud"});
    }
  }
  // Which cameras each source is asked for right now (every one while a cloud is watched).
  for (size_t i = 0; i < report.sources.size(); ++i) {
    SourceReport& source = report.sources[i];
    const auto r = rig(source.name);
    const bool all = channels_[i]->tap_count() > 0 || clouds(source.name).subscriber_count() > 0;
    std::vector<bool> used(r->cameras().size(), all);
    for (const auto& v : views) {
      const auto state = v->state();
      if (state->spec.source != source.name || v->subscriber_count() == 0) continue;
      for (size_t k = 0; k < used.size() && k < state->map->camera_used.size(); ++k) used[k] = used[k] || state->map->camera_used[k];
    }
    for (size_t k = 0; k < used.size(); ++k) {
      if (used[k]) source.active_cameras.push_back(r->cameras()[k].name);
    }
  }
  return report;
}

}  // namespace omniview
