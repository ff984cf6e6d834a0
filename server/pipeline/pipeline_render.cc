// The render worker (one per source) and the map rebuilds after a rig change.
#include "server/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <iostream>

#include <opencv2/core.hpp>

#include "core/map/apply.h"
#include "server/pipeline/frame_delivery.h"
#include "server/pipeline/frame_encoder.h"
#include "server/pipeline/staleness.h"
#include "server/pipeline/video_stream.h"

namespace omniview {

namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

void Pipeline::render_worker(SourceChannel* ch) {
  const std::string source = ch->source().name();
  while (true) {
    auto frames = ch->next(kStaleResendInterval);
    if (!frames) {
      if (ch->closed()) return;
      resend_stale_views(*ch);
      continue;
    }
    std::vector<std::shared_ptr<LiveView>> views;
    {
      std::lock_guard lock(views_mutex_);
      for (const auto& [_, v] : views_) {
        const auto state = v->state();
        if (state->spec.source != source) continue;
        if (v->subscriber_count() > 0) {
          views.push_back(v);
        } else if (frames->rig && frames->rig != state->rig) {
          // A source announces a new rig (a robot that just connected) with a frame set
          // that may hold no images at all: unwatched views rebuild too, so that their
          // cameras are known and get pulled once somebody watches.
          request_rebuild(state->spec.name);
        }
      }
    }
    // One view per task; apply_map inside runs single-threaded when nested, which is what
    // we want with several views, and uses the pool alone when there is one.
    if (!views.empty()) {
      cv::parallel_for_(cv::Range(0, static_cast<int>(views.size())), [&](const cv::Range& range) {
        for (int i = range.start; i < range.end; ++i) render_view(views[i], *frames);
      });
    }
    deliver_cloud(*ch, *frames);
    deliver_geometry(*ch, *frames);
  }
}

// The source is silent: its watched views, rendered again from its last images and marked.
// On the render worker's thread, so a view is never rendered by two threads at once.
void Pipeline::resend_stale_views(SourceChannel& ch) {
  const auto latest = ch.latest();
  if (!latest) return;
  std::vector<std::shared_ptr<LiveView>> views;
  {
    std::lock_guard lock(views_mutex_);
    for (const auto& [_, v] : views_) {
      if (v->state()->spec.source != ch.source().name()) continue;
      const auto subscribers = v->subscribers();
      if (std::any_of(subscribers.begin(), subscribers.end(),
                      [](const auto& s) { return s->stale_frames() || s->video(); })) {
        views.push_back(v);
      }
    }
  }
  const SourceStats stats = ch.stats();
  const SourceHealth health = ch.source().health();
  for (const auto& v : views) {
    const Staleness staleness = judge_staleness(ch.source().name(), stats, health, v->watched_since(), Clock::now());
    if (staleness.stale) render_view(v, *latest, &staleness);
  }
}

void Pipeline::render_view(const std::shared_ptr<LiveView>& view, const FrameSet& frames,
                           const Staleness* staleness) {
  const auto state = view->state();
  if (frames.rig && frames.rig != state->rig) request_rebuild(state->spec.name);
  const auto now = Clock::now();
  std::map<EncodingKey, std::vector<std::shared_ptr<Subscriber>>> groups;
  for (auto& s : view->subscribers()) {
    if (s->due(now) && (!staleness || s->stale_frames() || s->video())) groups[s->key()].push_back(s);
  }
  // A video group keeps one pace for all its clients (video_stream.h). Its clients all get
  // the stale re-renders (about one a second), asked for or not: every frame the shared
  // encoder codes is part of each client's stream.
  std::erase_if(groups, [&](const auto& group) {
    const auto& video = group.second.front()->video();
    return video && !staleness && !video->take_turn(now);
  });
  // An encoding that is behind (a PNG of a big view) still has a frame waiting: it gets
  // that one, and this frame set costs it nothing, not even the map's apply.
  std::erase_if(groups, [&](const auto& group) {
    if (!encoder_->behind(view.get(), group.first)) return false;
    for (const auto& s : group.second) s->count_dropped();
    return true;
  });
  if (groups.empty()) return;

  const FusionMap& map = *state->map;
  int channels = 1;
  for (size_t i = 0; i < map.camera_used.size(); ++i) {
    if (!map.camera_used[i]) continue;
    // A camera this view needs was not pulled (wanted cameras just changed): wait.
    if (i >= frames.images.size() || frames.images[i].empty()) return;
    channels = std::max(channels, frames.images[i].channels());
  }
  auto rendered = std::make_shared<RenderedFrame>();
  try {
    apply_map(map, frames.images, rendered->image, channels, view->update_gains(map, frames.images, channels));
  } catch (const std::exception& e) {
    // Images that do not fit the map (a rig change in flight): skip until the rebuild.
    request_rebuild(state->spec.name);
    return;
  }
  if (state->spec.overlay) {
    if (const auto it = robot_models_.find(state->spec.source); it != robot_models_.end()) {
      const Rig& rig = frames.rig ? *frames.rig : *state->rig;
      try {
        // Joints read now, after the subscribers were: a client that set joints and then
        // asked for a frame gets one that shows them (merged once, shared by the views).
        const auto joints = robot_joints_.at(state->spec.source)->effective(frames.joints);
        view->overlay(it->second).draw(rendered->image, state->spec, rig, joints);
      } catch (const std::exception& e) {
        // A render that fails (say, OSMesa out of memory) must not cost the view its frames.
        std::cerr << "omniviewd: view '" << state->spec.name << "': robot overlay skipped: " << e.what() << "\n";
      }
    }
  }
  rendered->sequence = frames.sequence;
  rendered->capture_time = frames.capture_time;
  rendered->arrival = frames.arrival;
  rendered->source_rate_hz = channel(state->spec.source).source().nominal_rate_hz();
  if (staleness) {
    rendered->stale = true;
    rendered->stale_reason = staleness->reason;
  }
  // Encoding is the encoder pool's: this thread goes on to the next view or frame set.
  const int width = rendered->image.cols, height = rendered->image.rows;
  for (auto& group : groups) {
    // Named copies: clang before 16 cannot capture structured bindings.
    const auto& key = group.first;
    const auto& subscribers = group.second;
    EncoderPool::Job job;
    job.run = [view, state, rendered, key, subscribers, video = subscribers.front()->video()] {
      encode_and_offer(*view, *state, *rendered, key, subscribers, video.get());
    };
    job.dropped = [subscribers] {
      for (const auto& s : subscribers) s->count_dropped();
    };
    encoder_->submit(view.get(), key, EncoderPool::expensive(key, width, height), std::move(job));
  }
}

void Pipeline::request_rebuild(const std::string& view) {
  {
    std::lock_guard lock(rebuild_mutex_);
    if (std::find(rebuild_queue_.begin(), rebuild_queue_.end(), view) != rebuild_queue_.end()) return;
    rebuild_queue_.push_back(view);
  }
  rebuild_ready_.notify_one();
}

void Pipeline::rebuild_worker() {
  while (true) {
    std::string name;
    {
      std::unique_lock lock(rebuild_mutex_);
      rebuild_ready_.wait(lock, [&] { return stopped_ || !rebuild_queue_.empty(); });
      if (stopped_) return;
      name = rebuild_queue_.front();
      rebuild_queue_.pop_front();
    }
    try {
      auto view = find_view(name);
      std::lock_guard change(view->change_mutex());
      const auto old = view->state();
      if (old->rig == rig(old->spec.source)) continue;  // an update got there first
      auto state = build_state(old->spec, old->revision);
      view->set_state(state);
      view->record_map_build(state->build_ms);
      update_wanted_cameras(old->spec.source);
    } catch (const std::exception& e) {
      // Deleted meanwhile, or the new rig no longer fits the view: keep the old map.
      std::cerr << "omniviewd: view '" << name << "': map not rebuilt for the new rig: " << e.what() << "\n";
    }
  }
}

}  // namespace omniview
