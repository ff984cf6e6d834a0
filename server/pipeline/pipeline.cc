// The pipeline's life (sources, start, stop), its lookups and the robot joints. Views,
// streams, rendering, clouds and status are in the pipeline_*.cc files beside it.
#include "server/pipeline/pipeline.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <thread>

#include "server/convert/convert.h"

namespace omniview {

namespace {

// Encoder threads: on a 2-core robot computer two cheap-lane threads (two views' JPEGs at
// once) and one expensive-lane thread; more on bigger machines.
int fast_encoder_threads() { return std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 2, 4); }
int slow_encoder_threads() { return std::clamp(static_cast<int>(std::thread::hardware_concurrency()) / 2, 1, 2); }

// Depth updates rest twice as long as each took: at most a third of one core for all depth
// views together (depth/depth_update_queue.h), the rest for frames.
constexpr double kDepthUpdateRest = 2.0;

}  // namespace

Pipeline::Pipeline(PipelineLimits limits) : limits_(limits) {}

Pipeline::~Pipeline() { stop("omniviewd is shutting down"); }

void Pipeline::add_source(std::unique_ptr<Source> source) {
  if (started_flag_) throw std::logic_error("add_source after start");
  for (const auto& c : channels_) {
    if (c->source().name() == source->name()) throw std::invalid_argument("two sources named '" + source->name() + "'");
  }
  clouds_[source->name()] = std::make_unique<CloudDelivery>(source->name());
  geometry_[source->name()] = std::make_unique<SourceGeometry>();
  channels_.push_back(std::make_unique<SourceChannel>(std::move(source)));
}

void Pipeline::set_robot_model(const std::string& source, std::shared_ptr<const RobotModelSetup> setup) {
  channel(source);  // NOT_FOUND for an unknown source
  robot_joints_[source] = std::make_unique<RobotJoints>(setup);
  clouds_.at(source)->set_robot_model(setup);
  robot_models_[source] = std::move(setup);
}

RobotJoints& Pipeline::robot_joints(const std::string& source) const {
  const std::string name = channel(source).source().name();  // NOT_FOUND for an unknown source
  const auto it = robot_joints_.find(name);
  if (it == robot_joints_.end()) {
    throw PipelineError(ErrorKind::kFailedPrecondition,
                        "source '" + name + "' has no robot model (robot_models in the daemon's config)");
  }
  return *it->second;
}

JointsReport Pipeline::set_joint_positions(const std::string& source, const JointMap& positions, bool clear) {
  RobotJoints& joints = robot_joints(source);
  joints.set(positions, clear);
  return joints.describe(channel(source).source().name());
}

JointsReport Pipeline::joint_positions(const std::string& source) const {
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
  depth_updates_ = std::make_unique<DepthUpdateQueue>([this](const std::string& view) { update_depth(view); },
                                                      kDepthUpdateRest);
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
    for (auto& [_, v] : views_) v->close_all(ErrorKind::kUnavailable, reason);
  }
  for (auto& c : channels_) c->close_taps(reason);
  for (auto& [_, c] : clouds_) c->close_all(ErrorKind::kUnavailable, reason);
  if (!started_flag_) return;
  for (auto& c : channels_) c->source().stop();
  for (auto& c : channels_) c->close();
  for (auto& w : workers_) w.join();
  depth_updates_->stop();  // after the render workers: nothing requests updates any more
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
  if (channels_.empty()) throw PipelineError(ErrorKind::kFailedPrecondition, "omniviewd has no sources configured");
  if (source.empty()) return *channels_.front();
  for (const auto& c : channels_) {
    if (c->source().name() == source) return *c;
  }
  std::string known;
  for (const auto& c : channels_) known += (known.empty() ? "" : ", ") + c->source().name();
  throw PipelineError(ErrorKind::kNotFound, "no source named '" + source + "' (sources: " + known + ")");
}

std::shared_ptr<LiveView> Pipeline::find_view(const std::string& name) const {
  std::lock_guard lock(views_mutex_);
  const auto it = views_.find(name);
  if (it == views_.end()) {
    std::string known;
    for (const auto& [n, _] : views_) known += (known.empty() ? "" : ", ") + n;
    throw PipelineError(ErrorKind::kNotFound,
                        "no view named '" + name + "' (views: " + (known.empty() ? "none" : known) + ")");
  }
  return it->second;
}

std::shared_ptr<const Rig> Pipeline::rig(const std::string& source) const {
  SourceChannel& ch = channel(source);
  if (const auto latest = ch.latest()) return latest->rig;
  return ch.source().rig();
}

std::vector<SourceCamera> Pipeline::cameras(const std::string& source) const {
  std::vector<SourceCamera> out;
  for (const auto& c : channels_) {
    if (!source.empty() && c->source().name() != source) continue;
    const auto r = rig(c->source().name());
    const auto checks = c->source().camera_checks();
    for (size_t i = 0; i < r->cameras().size(); ++i) {
      SourceCamera camera{c->source().name(), r, i, "", false};
      for (const auto& check : checks) {
        if (check.camera != r->cameras()[i].name) continue;
        camera.calibration_check = check.summary;
        camera.calibration_warning = check.warning;
      }
      out.push_back(std::move(camera));
    }
  }
  if (!source.empty() && out.empty()) channel(source);  // throws NOT_FOUND for an unknown name
  return out;
}

}  // namespace omniview
