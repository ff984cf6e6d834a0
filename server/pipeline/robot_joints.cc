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

v1::JointPositions RobotJoints::describe(const std::string& source) const {
  const robot::RobotModel& model = *setup_->model;
  std::lock_guard lock(mutex_);
  v1::JointPositions out;
  out.set_source(source);
  out.set_robot(model.name());
  for (const auto& name : model.variable_names()) {
    auto* j = out.add_joints();
    j->set_name(name);
    j->set_unit("rad");
    for (const auto& link : model.links()) {
      if (link.joint.name == name && link.joint.type == robot::JointType::kPrismatic) j->set_unit("m");
    }
    const std::pair<const JointMap*, v1::Joint::Origin> layers[] = {
        {&setup_->fixed_joints, v1::Joint::CONFIG}, {&api_, v1::Joint::API}, {live_.get(), v1::Joint::SOURCE}};
    for (const auto& [layer, origin] : layers) {
      if (!layer) continue;
      const auto it = layer->find(name);
      if (it == layer->end() || !std::isfinite(it->second)) continue;
      j->set_position(it->second);
      j->set_origin(origin);
    }
  }
  return out;
}

}  // namespace omniview
