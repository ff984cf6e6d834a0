// Who watches what: frame subscribers, recording taps, and which cameras they make the
// source pull.
#include "server/pipeline/pipeline.h"

#include <algorithm>
#include <cmath>

#include "server/pipeline/camera_sampling.h"
#include "server/pipeline/video_stream.h"

namespace omniview {

ViewSubscription Pipeline::subscribe(const std::string& name, const std::string& peer, EncodingKey key,
                                     double max_rate_hz, bool stale_frames) {
  if (stopped_) throw PipelineError(ErrorKind::kUnavailable, "omniviewd is shutting down");
  auto view = find_view(name);
  std::shared_ptr<Subscriber> s;
  if (key.encoding == v1::H264) {
    // Refused up front (too large a size) rather than ending the stream at its first frame.
    const auto state = view->state();
    video::H264Settings settings;
    settings.width = state->spec.width;
    settings.height = state->spec.height;
    try {
      video::check(settings);
    } catch (const std::invalid_argument& e) {
      throw PipelineError(ErrorKind::kInvalidArgument, "view '" + name + "': " + e.what());
    }
    key.rate_mhz = static_cast<int>(std::lround(max_rate_hz * 1000));
    s = std::make_shared<Subscriber>(peer, key, view->join_video(key), stale_frames);
  } else {
    s = std::make_shared<Subscriber>(peer, key, max_rate_hz, stale_frames);
  }
  view->add_subscriber(s);
  ViewSubscription held(s, [this, name](const Subscriber* left) { unsubscribe(name, left); });
  // After it is listed: an update from here on raises its floor itself, and one before has
  // its state in place already. Either way no frame of an older revision reaches it.
  s->set_min_revision(view->state()->revision);
  update_wanted_cameras(view->state()->spec.source);
  // A depth view watched again: never its old geometry (its first frame stands on its
  // fixed surface), and the source's newest geometry as soon as there is some.
  if (view->state()->depth) {
    {
      std::lock_guard change(view->change_mutex());
      drop_stale_geometry(*view);
    }
    if (depth_updates_) depth_updates_->request(name);
  }
  return held;
}

void Pipeline::unsubscribe(const std::string& name, const Subscriber* subscriber) {
  std::shared_ptr<LiveView> view;
  {
    std::lock_guard lock(views_mutex_);
    // The view may have been renamed or deleted meanwhile: search by subscriber.
    for (const auto& [n, v] : views_) {
      for (const auto& s : v->subscribers()) {
        if (s.get() == subscriber) view = v;
      }
    }
    if (!view) {
      const auto it = views_.find(name);
      if (it != views_.end()) view = it->second;
    }
  }
  if (!view) return;
  view->remove_subscriber(subscriber);
  update_wanted_cameras(view->state()->spec.source);
}

TapSubscription Pipeline::tap(const std::string& source, bool passive, TapLimits limits) {
  if (stopped_) throw PipelineError(ErrorKind::kUnavailable, "omniviewd is shutting down");
  SourceChannel& ch = channel(source);
  auto t = std::make_shared<FrameSetTap>(passive ? limits : limits_.record_queue);
  ch.add_tap(t, passive);
  TapSubscription held(t, [this, source](const FrameSetTap* left) { untap(source, left); });
  if (!passive) update_wanted_cameras(ch.source().name());
  return held;
}

void Pipeline::untap(const std::string& source, const FrameSetTap* t) {
  SourceChannel& ch = channel(source);
  ch.remove_tap(t);
  update_wanted_cameras(ch.source().name());
}

void Pipeline::update_wanted_cameras(const std::string& source) {
  SourceChannel* ch = nullptr;
  for (auto& c : channels_) {
    if (c->source().name() == source) ch = c.get();
  }
  if (!ch) return;
  const auto r = rig(source);
  std::vector<bool> wanted(r->cameras().size(), ch->tap_count() > 0);  // a recording takes everything
  std::vector<std::shared_ptr<LiveView>> views;
  {
    std::lock_guard lock(views_mutex_);
    for (const auto& [_, v] : views_) views.push_back(v);
  }
  // And how coarsely they sample each camera (the finest view decides; a recording
  // keeps full resolution).
  std::vector<double> spacing(wanted.size(), 0);
  const auto take_finest = [&](size_t i, double s) {
    if (s > 0) spacing[i] = spacing[i] == 0 ? s : std::min(spacing[i], s);
  };
  if (ch->tap_count() > 0) {
    for (size_t i = 0; i < spacing.size(); ++i) take_finest(i, 1.0 / std::max(1, r->cameras()[i].width));
  }
  for (const auto& v : views) {
    const auto state = v->state();
    if (state->spec.source != source || v->subscriber_count() == 0) continue;
    bool sees_any = false;
    for (size_t i = 0; i < wanted.size() && i < state->map->camera_used.size(); ++i) {
      if (state->map->camera_used[i]) wanted[i] = sees_any = true;
    }
    // A view no camera sees still gets its (black) frames, each saying coverage 0, at the
    // source's pace: image sets must keep coming, so one camera is asked for. Not while its
    // map is still the one of an older rig (a robot that just connected): that map knows
    // no cameras, and the rebuild says which ones it needs.
    if (!sees_any && state->rig == r && !wanted.empty()) wanted[0] = true;
    const auto sampling = camera_sampling(*state->map);
    for (size_t i = 0; i < spacing.size() && i < sampling.size(); ++i) take_finest(i, sampling[i]);
  }
  // A cloud is coloured from every camera, at full resolution; a recording keeps the
  // source's clouds too, watched or not.
  const bool cloud_wanted = clouds(source).subscriber_count() > 0 || ch->tap_count() > 0;
  if (cloud_wanted) {
    for (size_t i = 0; i < wanted.size(); ++i) {
      wanted[i] = true;
      take_finest(i, 1.0 / std::max(1, r->cameras()[i].width));
    }
  }
  // Sampling first: a source that starts decoding for a new watcher then decodes at the
  // size the views need from its first frame.
  ch->source().set_camera_sampling(spacing);
  // A watched depth view needs the clouds (and depth images), not every camera.
  const bool depth = depth_watched(source);
  ch->source().set_cloud_wanted(cloud_wanted || depth);
  ch->source().set_depth_wanted(depth);
  ch->source().set_wanted_cameras(wanted);
}

}  // namespace omniview
