// Views: create, update, delete, look up; clicks and points (PixelToRay, PointToPixel).
#include "server/pipeline/pipeline.h"

#include <chrono>
#include <iostream>

#include <yaml-cpp/yaml.h>

#include "core/io/quote.h"
#include "core/view/view_yaml.h"
#include "server/convert/convert.h"

namespace omniview {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// A depth view's update costs time and memory in proportion to its pixels (a 4096x4096 one
// took 8 s and 1.2 GB per update and slowed every other view): depth views stop at about
// 1920x1080.
constexpr int64_t kMaxDepthViewPixels = 2048LL * 1024;

}  // namespace

std::shared_ptr<const ViewState> Pipeline::build_state(const ViewSpec& spec, uint64_t revision) const {
  if (spec.name.empty()) throw PipelineError(ErrorKind::kInvalidArgument, "a view needs a name");
  const std::string what = "view " + quote_prefix(spec.name);
  if (static_cast<int64_t>(spec.width) * spec.height > limits_.max_view_pixels && spec.width > 0 && spec.height > 0) {
    throw PipelineError(ErrorKind::kInvalidArgument,
                        what + ": " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                            " pixels is more than this daemon allows (limits.max_view_pixels = " +
                            std::to_string(limits_.max_view_pixels) + ")");
  }
  // Before any map is built: refused at once.
  if (spec.depth == Depth::kMeasured && static_cast<int64_t>(spec.width) * spec.height > kMaxDepthViewPixels) {
    throw PipelineError(ErrorKind::kInvalidArgument,
                        what + ": depth: measured takes views of at most " + std::to_string(kMaxDepthViewPixels) +
                            " pixels (1920x1080 fits); this one has " + std::to_string(spec.width) + "x" +
                            std::to_string(spec.height));
  }
  try {
    validate(spec);  // the one check of every field, before anything uses one (CreateView, UpdateView, config)
  } catch (const std::invalid_argument& e) {
    throw PipelineError(ErrorKind::kInvalidArgument, e.what());
  }
  auto state = std::make_shared<ViewState>();
  state->spec = spec;
  state->revision = revision;
  try {
    state->view = View::create(spec);
  } catch (const std::invalid_argument& e) {
    throw PipelineError(ErrorKind::kInvalidArgument, e.what());
  }
  if (spec.overlay && !robot_models_.count(spec.source)) {
    throw PipelineError(ErrorKind::kInvalidArgument,
                        what + ": overlay needs a robot model for source '" + spec.source +
                            "' (robot_models in the daemon's config), and it has none");
  }
  state->rig = rig(spec.source);
  const Rig& r = *state->rig;
  const std::string frame = spec.frame.empty() ? r.default_frame() : spec.frame;
  if (!r.frames().has_frame(frame)) {
    std::string known;
    for (const auto& f : r.frames().frames()) known += (known.empty() ? "" : ", ") + f;
    throw PipelineError(ErrorKind::kInvalidArgument,
                        what + ": frame '" + frame + "' is not in source '" + channel(spec.source).source().name() +
                            "' (frames: " + known + ")");
  }
  const auto t0 = Clock::now();
  // A measured view's blend maps are rebuilt at every geometry update: its cameras' feather
  // weights are made once, here, for all of them.
  std::shared_ptr<const FeatherSet> feathers;
  if (spec.depth == Depth::kMeasured && spec.fusion == Fusion::kBlend) {
    feathers = std::make_shared<const FeatherSet>(feather_set(r, spec.feather_px));
  }
  try {
    state->map = std::make_shared<const FusionMap>(
        build_map(r, *state->view, MapPrecision::kAdaptive, Sampling::kFootprint, nullptr, feathers.get()));
  } catch (const std::invalid_argument& e) {
    throw PipelineError(ErrorKind::kInvalidArgument, e.what());
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
  if (spec.depth == Depth::kMeasured) {
    auto depth = std::make_shared<ViewDepth>();
    try {
      depth->surface = std::make_shared<const DepthSurface>(spec);
      depth->feathers = feathers;
    } catch (const std::invalid_argument& e) {
      throw PipelineError(ErrorKind::kInvalidArgument, e.what());
    }
    state->depth = std::move(depth);
    const auto geometry = this->geometry(channel(spec.source).source().name()).latest();
    if (geometry && fresh_geometry(geometry->ready, Clock::now())) {
      try {
        apply_measured_depth(*state, *geometry);
      } catch (const std::invalid_argument& e) {
        // Geometry of an older rig: the view starts on its fixed surface, the next cloud fixes it.
        std::cerr << "omniviewd: " << what << ": " << e.what() << "\n";
      }
    }
  }
  return state;
}

v1::View Pipeline::create_view(ViewSpec spec) {
  if (spec.source.empty()) spec.source = channel("").source().name();
  channel(spec.source);  // NOT_FOUND for an unknown source, before the expensive part
  {
    std::lock_guard lock(views_mutex_);
    if (views_.count(spec.name)) {
      throw PipelineError(ErrorKind::kAlreadyExists,
                          "a view named '" + spec.name + "' exists already (update it, or delete it first)");
    }
    if (static_cast<int>(views_.size()) >= limits_.max_views) {
      throw PipelineError(ErrorKind::kResourceExhausted,
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
      throw PipelineError(ErrorKind::kAlreadyExists, "a view named '" + spec.name + "' exists already");
    }
  }
  return *state->description;
}

v1::View Pipeline::update_view(const std::string& name, const std::function<void(ViewSpec&)>& change_spec) {
  auto view = find_view(name);
  std::lock_guard change(view->change_mutex());
  const auto old = view->state();
  ViewSpec spec = old->spec;
  try {
    change_spec(spec);
  } catch (const std::invalid_argument& e) {
    throw PipelineError(ErrorKind::kInvalidArgument, e.what());
  }
  if (spec.source.empty()) spec.source = channel("").source().name();
  channel(spec.source);
  const bool renamed = spec.name != name;
  if (renamed) {
    std::lock_guard lock(views_mutex_);
    if (views_.count(spec.name)) {
      throw PipelineError(ErrorKind::kAlreadyExists, "cannot rename view '" + name + "' to '" + spec.name +
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
    if (it == views_.end()) throw PipelineError(ErrorKind::kNotFound, "no view named '" + name + "'");
    view = it->second;
    views_.erase(it);
  }
  view->close_all(ErrorKind::kNotFound, "view '" + name + "' was deleted");
  update_wanted_cameras(view->state()->spec.source);
}

v1::View Pipeline::get_view(const std::string& name) const { return *find_view(name)->state()->description; }

std::vector<v1::View> Pipeline::list_views() const {
  std::vector<v1::View> out;
  std::lock_guard lock(views_mutex_);
  for (const auto& [_, v] : views_) out.push_back(*v->state()->description);
  return out;
}

PixelRay Pipeline::pixel_to_ray(const std::string& name, double u, double v) const {
  const auto state = find_view(name)->state();
  PixelRay r;
  r.robot_frame = state->description->robot_frame();
  r.origin = state->T_robot_view.translation();
  Vec3 dir;
  if (!std::isfinite(u) || !std::isfinite(v) || !state->view->pixel_to_direction(u, v, dir)) return r;
  dir.normalize();
  r.valid = true;
  r.direction_view = dir;
  r.direction = state->T_robot_view.linear() * dir;
  Vec3 point;
  if (state->view->pixel_to_point(u, v, point)) r.surface_point = state->T_robot_view * point;
  return r;
}

std::optional<Vec2> Pipeline::point_to_pixel(const std::string& name, const Vec3& point,
                                             const std::string& frame) const {
  const auto state = find_view(name)->state();
  const Rig& r = *state->rig;
  const std::string robot = r.default_frame();
  const auto T_robot_frame = r.frames().try_lookup(robot, frame.empty() ? robot : frame);
  if (!T_robot_frame) {
    throw PipelineError(ErrorKind::kInvalidArgument, "frame '" + frame + "' is not connected to '" + robot + "'");
  }
  const Vec3 p_view = state->T_robot_view.inverse() * (*T_robot_frame * point);
  Vec2 uv;
  if (!state->view->point_to_pixel(p_view, uv)) return std::nullopt;
  return uv;
}

}  // namespace omniview
