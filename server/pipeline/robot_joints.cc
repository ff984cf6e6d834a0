#include "server/pipeline/robot_joints.h"

#include <cmath>

#include "server/pipeline/errors.h"

namespace omniview {

RobotJoints::RobotJoints(std::shared_ptr<const RobotModelSetup> setup) : setup_(std::move(setup)) {}

void RobotJoints::set(const JointMap& updates, bool clear) {
  const robot::RobotModel& model = *setup_->model;
  for (const auto& [name, value] : updates) {
    if (model.variable_index(name) < 0) {
      std::string known;
      for (const auto& n : model.variable_names()) known += (known.empty() ? "" : ", ") + n;
      throw PipelineError(ErrorKind::kInvalidArgument,
                          "robot '" + model.name() + "' has no movable joint '" + name + "' (it has: " +
                              (known.empty() ? "none" : known) + ")");
    }
    if (!std::isfinite(value)) {
      throw PipelineError(ErrorKind::kInvalidArgument, "joint '" + name + "': position must be a finite number");
    }
  }
  try {
    model.check_limits(updates);
  } catch (const std::invalid_argument& e) {
    throw PipelineError(ErrorKind::kInvalidArgument, e.what());
  }
  std::lock_guard lock(mutex_);
  if (clear) api_.clear();
  for (const auto& [name, value] : updates) api_[name] = value;
  ++api_version_;
}

std::shared_ptr<const JointMap> RobotJoints::effective(const std::shared_ptr<const JointMap>& live) {
  std::lock_guard lock(mutex_);
  if (live) live_ = live;
  if (merged_ && merged_api_version_ == api_version_ && merged_live_ == live_) return merged_;
  const robot::RobotModel& model = *setup_->model;
  auto merged = std::make_shared<JointMap>();
  for (const auto& name : model.variable_names()) (*merged)[name] = 0.0;
  const JointMap* layers[] = {&setup_->fixed_joints, &api_, live_.get()};
  for (const JointMap* layer : layers) {
    if (!layer) continue;
    for (const auto& [name, value] : *layer) {
      if (model.variable_index(name) >= 0 && std::isfinite(value)) (*merged)[name] = value;
    }
  }
  merged_ = std::move(merged);
  merged_api_version_ = api_version_;
  merged_live_ = live_;
  return merged_;
}

JointsReport RobotJoints::describe(const std::string& source) const {
  const robot::RobotModel& model = *setup_->model;
  std::lock_guard lock(mutex_);
  JointsReport out;
  out.source = source;
  out.robot = model.name();
  for (const auto& name : model.variable_names()) {
    JointReport& j = out.joints.emplace_back();
    j.name = name;
    for (const auto& link : model.links()) {
      if (link.joint.name == name && link.joint.type == robot::JointType::kPrismatic) j.unit = "m";
    }
    using Origin = JointReport::Origin;
    const std::pair<const JointMap*, Origin> layers[] = {
        {&setup_->fixed_joints, Origin::kConfig}, {&api_, Origin::kApi}, {live_.get(), Origin::kSource}};
    for (const auto& [layer, origin] : layers) {
      if (!layer) continue;
      const auto it = layer->find(name);
      if (it == layer->end() || !std::isfinite(it->second)) continue;
      j.position = it->second;
      j.origin = origin;
    }
  }
  return out;
}

}  // namespace omniview
