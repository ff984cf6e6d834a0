// GetStatus: sources, views, clients and the cameras being pulled.
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

void Pipeline::set_status_extension(std::function<void(v1::Status&)> extension) {
  std::lock_guard lock(status_extension_mutex_);
  status_extension_ = std::move(extension);
}

v1::Status Pipeline::status() const {
  v1::Status st;
  st.set_version("0.1.0");
  st.set_uptime_s(std::chrono::duration<double>(Clock::now() - started_).count());
  const auto now = Clock::now();
  for (const auto& c : channels_) {
    const auto stats = c->stats();
    const auto health = c->source().health();
    auto* s = st.add_sources();
    s->set_name(c->source().name());
    s->set_type(c->source().type());
    s->set_connected(health.connected);
    const bool any = stats.last_arrival.time_since_epoch().count() != 0;
    const double age = any ? std::chrono::duration<double>(now - stats.last_arrival).count() : -1;
    s->set_last_frame_age_s(age);
    // The averaged rate means nothing once frames stop coming.
    s->set_rate_hz(any && age < 2 + (stats.rate_hz > 0 ? 2 / stats.rate_hz : 0) ? stats.rate_hz : 0);
    s->set_frames(stats.frames);
    s->set_errors(health.errors);
    s->set_dropped(stats.dropped);
    s->set_message(health.message);
    s->set_failure_rate(health.failure_rate);
    s->set_degraded(health.connected && health.failure_rate >= kDegradedFailureRate);
  }
  std::vector<std::shared_ptr<LiveView>> views;
  {
    std::lock_guard lock(views_mutex_);
    for (const auto& [_, v] : views_) views.push_back(v);
  }
  for (const auto& v : views) {
    const auto state = v->state();
    const auto stats = v->stats();
    auto* s = st.add_views();
    s->set_name(state->spec.name);
    const auto subscribers = v->subscribers();
    s->set_subscribers(static_cast<uint32_t>(subscribers.size()));
    const bool recent = stats.last_frame.time_since_epoch().count() != 0 &&
                        std::chrono::duration<double>(now - stats.last_frame).count() < 2;
    s->set_fps(recent ? stats.fps : 0);
    s->set_frames(stats.frames);
    s->set_map_rebuilds(stats.map_rebuilds);
    s->set_last_map_build_ms(stats.last_map_build_ms);
    s->set_coverage(state->coverage);
    const auto current = rig(state->spec.source);
    s->set_map_pending(current && current != state->rig);
    s->set_last_latency_ms(stats.last_latency_ms);
    if (state->depth) {
      describe_depth(*state, subscribers.size(), *s);
      s->set_depth_updates(stats.depth_updates);
    }
    for (const auto& sub : subscribers) {
      auto* c = st.add_clients();
      c->set_peer(sub->peer());
      c->set_view(state->spec.name);
      c->set_frames_sent(sub->frames_sent());
      c->set_frames_dropped(sub->frames_dropped());
      c->set_encoding(to_string(sub->key()));
    }
  }
  // Cloud clients, named by their source's cloud.
  for (const auto& [source, delivery] : clouds_) {
    for (const auto& sub : delivery->subscribers()) {
      auto* c = st.add_clients();
      c->set_peer(sub->peer());
      c->set_view("cloud:" + source);
      c->set_frames_sent(sub->clouds_sent());
      c->set_frames_dropped(sub->clouds_dropped());
      c->set_encoding("cloud");
    }
  }
  // Which cameras each source is asked for right now (every one while a cloud is watched).
  for (int i = 0; i < st.sources_size(); ++i) {
    const auto r = rig(st.sources(i).name());
    const bool all = channels_[i]->tap_count() > 0 || clouds(st.sources(i).name()).subscriber_count() > 0;
    std::vector<bool> used(r->cameras().size(), all);
    for (const auto& v : views) {
      const auto state = v->state();
      if (state->spec.source != st.sources(i).name() || v->subscriber_count() == 0) continue;
      for (size_t k = 0; k < used.size() && k < state->map->camera_used.size(); ++k) used[k] = used[k] || state->map->camera_used[k];
    }
    for (size_t k = 0; k < used.size(); ++k) {
      if (used[k]) st.mutable_sources(i)->add_active_cameras(r->cameras()[k].name);
    }
  }
  {
    std::lock_guard lock(status_extension_mutex_);
    if (status_extension_) status_extension_(st);
  }
  return st;
}

}  // namespace omniview
