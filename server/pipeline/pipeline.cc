#include "server/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <thread>

#include <opencv2/core.hpp>
#include <yaml-cpp/yaml.h>

#include "core/io/quote.h"
#include "core/map/apply.h"
#include "core/view/view_yaml.h"
#include "server/convert/convert.h"
#include "server/pipeline/camera_sampling.h"
#include "server/pipeline/frame_delivery.h"
#include "server/pipeline/frame_encoder.h"

namespace omniview {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Encoder threads: on a 2-core robot computer two cheap-lane threads (two views' JPEGs at
// once) and one expensive-lane thread; more on bigger machines.
int fast_encoder_threads() { return std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 2, 4); }
int slow_encoder_threads() { return std::clamp(static_cast<int>(std::thread::hardware_concurrency()) / 2, 1, 2); }

}  // namespace

Pipeline::Pipeline(PipelineLimits limits) : limits_(limits) {}

Pipeline::~Pipeline() { stop("omniviewd is shutting down"); }

void Pipeline::add_source(std::unique_ptr<Source> source) {
  if (started_flag_) throw std::logic_error("add_source after start");
  for (const auto& c : channels_) {
    if (c->source().name() == source->name()) throw std::invalid_argument("two sources named '" + source->name() + "'");
  }
  channels_.push_back(std::make_unique<SourceChannel>(std::move(source)));
}

void Pipeline::set_robot_model(const std::string& source, std::shared_ptr<const RobotModelSetup> setup) {
  channel(source);  // NOT_FOUND for an unknown source
  robot_joints_[source] = std::make_unique<RobotJoints>(setup);
  robot_models_[source] = std::move(setup);
}

RobotJoints& Pipeline::robot_joints(const std::string& source) const {
  const std::string name = channel(source).source().name();  // NOT_FOUND for an unknown source
  const auto it = robot_joints_.find(name);
  if (it == robot_joints_.end()) {
    throw ApiError(grpc::StatusCode::FAILED_PRECONDITION,
                   "source '" + name + "' has no robot model (robot_models in the daemon's config)");
  }
  return *it->second;
}

v1::JointPositions Pipeline::set_joint_positions(const std::string& source, const JointMap& positions, bool clear) {
  RobotJoints& joints = robot_joints(source);
  joints.set(positions, clear);
  return joints.describe(channel(source).source().name());
}

v1::JointPositions Pipeline::joint_positions(const std::string& source) const {
  RobotJoints& joints = robot_joints(source);
  const Source& s = channel(source).source();
  // The source's newest report, not only the last frame's: nobody may be watching.
  if (auto live = s.latest_joints()) joints.effective(live);
  return joints.describe(s.name());
}

void Pipeline::start() {
  if (started_flag_.exchange(true)) return;
  encoder_ = std::make_unique<EncoderPool>(fast_encoder_threads(), slow_encoder_threads());
  rebuild_thread_ = std::thread([this] { rebuild_worker(); });
  for (auto& c : channels_) {
    SourceChannel* ch = c.get();
    workers_.emplace_back([this, ch] { render_worker(ch); });
    update_wanted_cameras(ch->source().name());
    ch->source().start([ch](std::shared_ptr<const FrameSet> frames) { ch->deliver(std::move(frames)); });
  }
}

void Pipeline::stop(const std::string& reason) {
  if (stopped_.exchange(true)) return;
  {
    std::lock_guard lock(views_mutex_);
    for (auto& [_, v] : views_) v->close_all(grpc::StatusCode::UNAVAILABLE, reason);
  }
  for (auto& c : channels_) c->close_taps(reason);
  if (!started_flag_) return;
  for (auto& c : channels_) c->source().stop();
  for (auto& c : channels_) c->close();
  for (auto& w : workers_) w.join();
  // After the render workers: nothing submits any more. Encodes in flight finish and offer
  // to subscribers that are closed by now, which refuse them.
  encoder_->stop();
  {
    std::lock_guard lock(rebuild_mutex_);
  }
  rebuild_ready_.notify_all();
  rebuild_thread_.join();
}

// ---------------------------------------------------------------- lookups

SourceChannel& Pipeline::channel(const std::string& source) const {
  if (channels_.empty()) throw ApiError(grpc::StatusCode::FAILED_PRECONDITION, "omniviewd has no sources configured");
  if (source.empty()) return *channels_.front();
  for (const auto& c : channels_) {
    if (c->source().name() == source) return *c;
  }
  std::string known;
  for (const auto& c : channels_) known += (known.empty() ? "" : ", ") + c->source().name();
  throw ApiError(grpc::StatusCode::NOT_FOUND, "no source named '" + source + "' (sources: " + known + ")");
}

std::shared_ptr<LiveView> Pipeline::find_view(const std::string& name) const {
  std::lock_guard lock(views_mutex_);
  const auto it = views_.find(name);
  if (it == views_.end()) {
    std::string known;
    for (const auto& [n, _] : views_) known += (known.empty() ? "" : ", ") + n;
    throw ApiError(grpc::StatusCode::NOT_FOUND,
                   "no view named '" + name + "' (views: " + (known.empty() ? "none" : known) + ")");
  }
  return it->second;
}

std::shared_ptr<const Rig> Pipeline::rig(const std::string& source) const {
  SourceChannel& ch = channel(source);
  if (const auto latest = ch.latest()) return latest->rig;
  return ch.source().rig();
}

std::vector<v1::Camera> Pipeline::cameras(const std::string& source) const {
  std::vector<v1::Camera> out;
  for (const auto& c : channels_) {
    if (!source.empty() && c->source().name() != source) continue;
    const auto r = rig(c->source().name());
    for (const auto& cam : r->cameras()) out.push_back(to_proto(cam, *r, c->source().name()));
  }
  if (!source.empty() && out.empty()) channel(source);  // throws NOT_FOUND for an unknown name
  return out;
}

// ---------------------------------------------------------------- views

std::shared_ptr<const ViewState> Pipeline::build_state(const ViewSpec& spec, uint64_t revision) const {
  if (spec.name.empty()) throw ApiError(grpc::StatusCode::INVALID_ARGUMENT, "a view needs a name");
  const std::string what = "view " + quote_prefix(spec.name);
  if (static_cast<int64_t>(spec.width) * spec.height > limits_.max_view_pixels && spec.width > 0 && spec.height > 0) {
    throw ApiError(grpc::StatusCode::INVALID_ARGUMENT,
                   what + ": " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                       " pixels is more than this daemon allows (limits.max_view_pixels = " +
                       std::to_string(limits_.max_view_pixels) + ")");
  }
  try {
    validate(spec);  // the one check of every field, before anything uses one (CreateView, UpdateView, config)
  } catch (const std::invalid_argument& e) {
    throw ApiError(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  }
  auto state = std::make_shared<ViewState>();
  state->spec = spec;
  state->revision = revision;
  try {
    state->view = View::create(spec);
  } catch (const std::invalid_argument& e) {
    throw ApiError(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  }
  if (spec.overlay && !robot_models_.count(spec.source)) {
    throw ApiError(grpc::StatusCode::INVALID_ARGUMENT,
                   what + ": overlay needs a robot model for source '" + spec.source +
                       "' (robot_models in the daemon's config), and it has none");
  }
  state->rig = rig(spec.source);
  const Rig& r = *state->rig;
  const std::string frame = spec.frame.empty() ? r.default_frame() : spec.frame;
  if (!r.frames().has_frame(frame)) {
    std::string known;
    for (const auto& f : r.frames().frames()) known += (known.empty() ? "" : ", ") + f;
    throw ApiError(grpc::StatusCode::INVALID_ARGUMENT,
                   what + ": frame '" + frame + "' is not in source '" + channel(spec.source).source().name() +
                       "' (frames: " + known + ")");
  }
  const auto t0 = Clock::now();
  try {
    state->map = std::make_shared<const FusionMap>(build_map(r, *state->view));
  } catch (const std::invalid_argument& e) {
    throw ApiError(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  }
  state->build_ms = ms_since(t0);
  state->coverage = state->map->coverage();

  auto d = std::make_shared<v1::View>();
  *d->mutable_spec() = to_proto(spec);
  d->set_revision(revision);
  for (double v : pinhole_intrinsics(*state->view)) d->add_intrinsics(v);
  d->set_robot_frame(r.default_frame());
  const Pose T_robot_view = r.frames().lookup(r.default_frame(), frame) * spec.T_frame_view();
  *d->mutable_pose() = to_proto(T_robot_view);
  YAML::Emitter yaml;
  yaml.SetDoublePrecision(12);  // 0.42, not 0.41999999999999998: people read and edit it
  yaml << view_to_yaml(spec);
  d->set_yaml(yaml.c_str());
  state->T_robot_view = T_robot_view;
  state->description = std::move(d);
  return state;
}

v1::View Pipeline::create_view(ViewSpec spec) {
  if (spec.source.empty()) spec.source = channel("").source().name();
  channel(spec.source);  // NOT_FOUND for an unknown source, before the expensive part
  {
    std::lock_guard lock(views_mutex_);
    if (views_.count(spec.name)) {
      throw ApiError(grpc::StatusCode::ALREADY_EXISTS,
                     "a view named '" + spec.name + "' exists already (update it, or delete it first)");
    }
    if (static_cast<int>(views_.size()) >= limits_.max_views) {
      throw ApiError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                     "this daemon keeps at most " + std::to_string(limits_.max_views) +
                         " views (limits.max_views); delete one first");
    }
  }
  auto state = build_state(spec, 1);
  auto view = std::make_shared<LiveView>(state);
  view->record_map_build(state->build_ms);
  {
    std::lock_guard lock(views_mutex_);
    if (!views_.emplace(spec.name, view).second) {
      throw ApiError(grpc::StatusCode::ALREADY_EXISTS, "a view named '" + spec.name + "' exists already");
    }
  }
  return *state->description;
}

v1::View Pipeline::update_view(const std::string& name, const v1::ViewSpec& set, const v1::ViewDelta& delta) {
  auto view = find_view(name);
  std::lock_guard change(view->change_mutex());
  const auto old = view->state();
  ViewSpec spec = old->spec;
  try {
    apply_patch(set, spec);
    apply_delta(delta, spec);
  } catch (const std::invalid_argument& e) {
    throw ApiError(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  }
  if (spec.source.empty()) spec.source = channel("").source().name();
  channel(spec.source);
  const bool renamed = spec.name != name;
  if (renamed) {
    std::lock_guard lock(views_mutex_);
    if (views_.count(spec.name)) {
      throw ApiError(grpc::StatusCode::ALREADY_EXISTS, "cannot rename view '" + name + "' to '" + spec.name +
                                                           "': a view of that name exists");
    }
  }
  auto state = build_state(spec, old->revision + 1);
  view->set_state(state);
  view->record_map_build(state->build_ms);
  for (const auto& s : view->subscribers()) s->set_min_revision(state->revision);
  if (renamed) {
    std::lock_guard lock(views_mutex_);
    views_.erase(name);
    views_.emplace(spec.name, view);
  }
  update_wanted_cameras(spec.source);
  if (old->spec.source != spec.source) update_wanted_cameras(old->spec.source);
  return *state->description;
}

void Pipeline::delete_view(const std::string& name) {
  std::shared_ptr<LiveView> view;
  {
    std::lock_guard lock(views_mutex_);
    const auto it = views_.find(name);
    if (it == views_.end()) throw ApiError(grpc::StatusCode::NOT_FOUND, "no view named '" + name + "'");
    view = it->second;
    views_.erase(it);
  }
  view->close_all(grpc::StatusCode::NOT_FOUND, "view '" + name + "' was deleted");
  update_wanted_cameras(view->state()->spec.source);
}

v1::View Pipeline::get_view(const std::string& name) const { return *find_view(name)->state()->description; }

std::vector<v1::View> Pipeline::list_views() const {
  std::vector<v1::View> out;
  std::lock_guard lock(views_mutex_);
  for (const auto& [_, v] : views_) out.push_back(*v->state()->description);
  return out;
}

v1::PixelToRayResponse Pipeline::pixel_to_ray(const std::string& name, double u, double v) const {
  const auto state = find_view(name)->state();
  v1::PixelToRayResponse r;
  r.set_robot_frame(state->description->robot_frame());
  *r.mutable_origin() = to_proto(Vec3(state->T_robot_view.translation()));
  Vec3 dir;
  if (!std::isfinite(u) || !std::isfinite(v) || !state->view->pixel_to_direction(u, v, dir)) return r;
  dir.normalize();
  r.set_valid(true);
  *r.mutable_direction_view() = to_proto(dir);
  *r.mutable_direction() = to_proto(Vec3(state->T_robot_view.linear() * dir));
  Vec3 point;
  if (state->view->pixel_to_point(u, v, point)) *r.mutable_surface_point() = to_proto(Vec3(state->T_robot_view * point));
  return r;
}

v1::PointToPixelResponse Pipeline::point_to_pixel(const std::string& name, const Vec3& point,
                                                  const std::string& frame) const {
  const auto state = find_view(name)->state();
  const Rig& r = *state->rig;
  const std::string robot = r.default_frame();
  const auto T_robot_frame = r.frames().try_lookup(robot, frame.empty() ? robot : frame);
  if (!T_robot_frame) {
    throw ApiError(grpc::StatusCode::INVALID_ARGUMENT, "frame '" + frame + "' is not connected to '" + robot + "'");
  }
  const Vec3 p_view = state->T_robot_view.inverse() * (*T_robot_frame * point);
  v1::PointToPixelResponse out;
  Vec2 uv;
  if (state->view->point_to_pixel(p_view, uv)) {
    out.set_visible(true);
    out.set_u(uv.x());
    out.set_v(uv.y());
  }
  return out;
}

// ---------------------------------------------------------------- subscribers

std::shared_ptr<Subscriber> Pipeline::subscribe(const std::string& name, const std::string& peer, EncodingKey key,
                                                double max_rate_hz) {
  if (stopped_) throw ApiError(grpc::StatusCode::UNAVAILABLE, "omniviewd is shutting down");
  auto view = find_view(name);
  auto s = std::make_shared<Subscriber>(peer, key, max_rate_hz);
  view->add_subscriber(s);
  update_wanted_cameras(view->state()->spec.source);
  return s;
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

std::shared_ptr<FrameSetTap> Pipeline::tap(const std::string& source) {
  if (stopped_) throw ApiError(grpc::StatusCode::UNAVAILABLE, "omniviewd is shutting down");
  SourceChannel& ch = channel(source);
  auto t = std::make_shared<FrameSetTap>(limits_.record_queue);
  ch.add_tap(t);
  update_wanted_cameras(ch.source().name());
  return t;
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
    for (size_t i = 0; i < wanted.size() && i < state->map->camera_used.size(); ++i) {
      if (state->map->camera_used[i]) wanted[i] = true;
    }
    const auto sampling = camera_sampling(*state->map);
    for (size_t i = 0; i < spacing.size() && i < sampling.size(); ++i) take_finest(i, sampling[i]);
  }
  // Sampling first: a source that starts decoding for a new watcher then decodes at the
  // size the views need from its first frame.
  ch->source().set_camera_sampling(spacing);
  ch->source().set_wanted_cameras(wanted);
}

// ---------------------------------------------------------------- rendering

void Pipeline::render_worker(SourceChannel* ch) {
  const std::string source = ch->source().name();
  while (auto frames = ch->next()) {
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
    if (views.empty()) continue;  // nobody watching: nothing to do
    // One view per task; apply_map inside runs single-threaded when nested, which is what
    // we want with several views, and uses the pool alone when there is one.
    cv::parallel_for_(cv::Range(0, static_cast<int>(views.size())), [&](const cv::Range& range) {
      for (int i = range.start; i < range.end; ++i) render_view(views[i], *frames);
    });
  }
}

void Pipeline::render_view(const std::shared_ptr<LiveView>& view, const FrameSet& frames) {
  const auto state = view->state();
  if (frames.rig && frames.rig != state->rig) request_rebuild(state->spec.name);
  const auto now = Clock::now();
  std::map<EncodingKey, std::vector<std::shared_ptr<Subscriber>>> groups;
  for (auto& s : view->subscribers()) {
    if (s->due(now)) groups[s->key()].push_back(s);
  }
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
  // Encoding is the encoder pool's: this thread goes on to the next view or frame set.
  const int width = rendered->image.cols, height = rendered->image.rows;
  for (auto& [key, subscribers] : groups) {
    EncoderPool::Job job;
    job.run = [view, state, rendered, key, subscribers] {
      encode_and_offer(*view, *state, *rendered, key, subscribers);
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

// ---------------------------------------------------------------- status

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
    s->set_last_latency_ms(stats.last_latency_ms);
    for (const auto& sub : subscribers) {
      auto* c = st.add_clients();
      c->set_peer(sub->peer());
      c->set_view(state->spec.name);
      c->set_frames_sent(sub->frames_sent());
      c->set_frames_dropped(sub->frames_dropped());
      c->set_encoding(to_string(sub->key()));
    }
  }
  // Which cameras each source is asked for right now.
  for (int i = 0; i < st.sources_size(); ++i) {
    const auto r = rig(st.sources(i).name());
    std::vector<bool> used(r->cameras().size(), channels_[i]->tap_count() > 0);
    for (const auto& v : views) {
      const auto state = v->state();
      if (state->spec.source != st.sources(i).name() || v->subscriber_count() == 0) continue;
      for (size_t k = 0; k < used.size() && k < state->map->camera_used.size(); ++k) used[k] = used[k] || state->map->camera_used[k];
    }
    for (size_t k = 0; k < used.size(); ++k) {
      if (used[k]) st.mutable_sources(i)->add_active_cameras(r->cameras()[k].name);
    }
  }
  return st;
}

}  // namespace omniview
