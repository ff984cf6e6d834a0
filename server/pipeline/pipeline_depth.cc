// Measured depth (`depth: measured`): each source's lidar clouds join its geometry on the
// render worker, and the depth thread (depth/depth_update_queue.h) rebuilds the watched
// depth views' maps on it, swapping each in like any other map: frames keep flowing with
// the previous one meanwhile.
#include <chrono>
#include <iostream>

#include "core/depth/camera_occluders.h"
#include "server/pipeline/pipeline.h"

namespace omniview {

namespace {

using DepthClock = std::chrono::steady_clock;

}  // namespace

SourceGeometry& Pipeline::geometry(const std::string& source) const { return *geometry_.at(source); }

bool Pipeline::depth_watched(const std::string& source) const {
  std::lock_guard lock(views_mutex_);
  for (const auto& [_, v] : views_) {
    const auto state = v->state();
    if (state->depth && state->spec.source == source && v->subscriber_count() > 0) return true;
  }
  return false;
}

void Pipeline::deliver_geometry(SourceChannel& ch, const FrameSet& frames) {
  const std::string& name = ch.source().name();
  std::vector<std::string> watched, stale;
  {
    std::lock_guard lock(views_mutex_);
    for (const auto& [view, v] : views_) {
      const auto state = v->state();
      if (!state->depth || state->spec.source != name || v->subscriber_count() == 0) continue;
      watched.push_back(view);
      if (state->depth->geometry_version != 0 &&
          !fresh_geometry(state->depth->geometry_ready, DepthClock::now())) {
        stale.push_back(view);
      }
    }
  }
  if (!frames.cloud && frames.depth.empty()) {
    // The lidar went quiet while watched: such a view returns to its fixed surface.
    for (const auto& view : stale) depth_updates_->request(view);
    return;
  }
  if (watched.empty()) return;
  const auto rig = frames.rig ? frames.rig : this->rig(name);
  std::vector<const PointCloud*> clouds;
  if (frames.cloud) clouds.push_back(frames.cloud.get());
  for (const auto& d : frames.depth) clouds.push_back(d.get());
  geometry(name).add(clouds, *rig, frames.motion.get(), frames.arrival);
  for (const auto& view : watched) depth_updates_->request(view);
}

void Pipeline::update_depth(const std::string& name) {
  std::shared_ptr<LiveView> view;
  {
    std::lock_guard lock(views_mutex_);
    const auto it = views_.find(name);
    if (it == views_.end()) return;  // deleted or renamed meanwhile
    view = it->second;
  }
  if (view->subscriber_count() == 0) return;
  std::lock_guard change(view->change_mutex());
  const auto old = view->state();
  if (!old->depth) return;  // made fixed meanwhile
  const auto now = DepthClock::now();
  const auto snapshot = geometry(old->spec.source).latest();
  if (snapshot && fresh_geometry(snapshot->ready, now)) {
    if (snapshot->version == old->depth->geometry_version) return;
    auto state = std::make_shared<ViewState>(*old);
    apply_measured_depth(*state, *snapshot);
    view->set_state(state);
    view->record_depth_update();
  } else {
    drop_stale_geometry(*view);
  }
}

void Pipeline::drop_stale_geometry(LiveView& view) {
  const auto old = view.state();
  if (!old->depth || old->depth->geometry_version == 0) return;
  if (fresh_geometry(old->depth->geometry_ready, DepthClock::now())) return;
  // Geometry from the last time someone watched (or before the lidar went quiet): the
  // fixed surface until new geometry comes, never a world that may have moved since.
  try {
    view.set_state(build_state(old->spec, old->revision));
  } catch (const std::exception& e) {
    // The view no longer fits its source's rig (a rig change in flight): the rebuild for
    // that comes; the old map stays until then.
    std::cerr << "omniviewd: view '" << old->spec.name << "': old geometry not dropped: " << e.what() << "\n";
  }
}

void Pipeline::apply_measured_depth(ViewState& state, const GeometrySnapshot& geometry) const {
  const auto t0 = DepthClock::now();
  const Rig& rig = *state.rig;
  const auto T_robot_points = rig.frames().try_lookup(rig.default_frame(), geometry.frame);
  if (!T_robot_points) {
    throw std::invalid_argument("the geometry's frame '" + geometry.frame + "' is not connected to the rig's '" +
                                rig.default_frame() + "'");
  }
  const Pose T_view_points = state.T_robot_view.inverse() * *T_robot_points;
  auto depth = std::make_shared<ViewDepth>(*state.depth);
  const auto view = depth->surface->update(*geometry.points, T_view_points, nullptr,
                                           geometry.completion ? &geometry.completion->get().points : nullptr);
  // The cameras' occluders are the geometry's, shared by the source's depth views; the
  // pixels judged are this view's.
  const auto occluders = this->geometry(state.spec.source).occluders(geometry, state.rig, ViewOcclusionOptions{});
  const Occlusion occlusion = for_view(*occluders, *view);
  state.map = std::make_shared<const FusionMap>(build_map(rig, *view, MapPrecision::kAdaptive, Sampling::kFootprint, &occlusion,
                                                                depth->feathers.get()));
  state.view = view;
  state.coverage = state.map->coverage();
  depth->geometry_version = geometry.version;
  depth->geometry_arrival = geometry.arrival;
  depth->geometry_ready = geometry.ready;
  depth->measured_fraction = view->measured_fraction();
  depth->update_ms = std::chrono::duration<double, std::milli>(DepthClock::now() - t0).count();
  state.depth = std::move(depth);
}

DepthReport Pipeline::describe_depth(const ViewState& state, size_t subscribers) const {
  DepthReport report;
  const ViewDepth& depth = *state.depth;
  const bool any = depth.geometry_version != 0;
  report.geometry_age_s = any ? std::chrono::duration<double>(DepthClock::now() - depth.geometry_arrival).count() : -1;
  report.update_ms = depth.update_ms;
  // Unwatched, the share is what a new watcher would get: 0, for a view watched again starts
  // on its fixed surface (its old geometry is dropped); the last share, shown before, read as
  // if the view still stood on measured depth (a reviewer's finding).
  report.measured_fraction = subscribers == 0 ? 0 : depth.measured_fraction;
  const Source& source = channel(state.spec.source).source();
  const SourceGeometry& g = geometry(source.name());
  if (!source.provides_clouds() && !any) {
    report.message = "source '" + source.name() + "' (type " + source.type() +
                     ") delivers no lidar clouds: the view stands on its fixed surface";
  } else if (!g.message().empty()) {
    report.message = g.message();
  } else if (subscribers == 0) {
    report.message = "not watched: the surface follows the lidar and depth cameras only while someone watches the view";
  } else if (!any) {
    report.message = "waiting for the source's first lidar cloud or depth image";
  }
  return report;
}

}  // namespace omniview
