#include "core/robot/model/robot_model.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace omniview::robot {

RobotModel::RobotModel(std::string name, std::vector<Link> links, std::vector<Visual> visuals,
                       std::vector<std::string> variable_names)
    : name_(std::move(name)), links_(std::move(links)), visuals_(std::move(visuals)),
      variable_names_(std::move(variable_names)) {
  for (size_t i = 0; i < links_.size(); ++i) {
    if (links_[i].parent >= static_cast<int>(i)) throw std::logic_error("RobotModel: links must be stored parents first");
  }
  for (size_t i = 0; i < variable_names_.size(); ++i) variable_index_[variable_names_[i]] = static_cast<int>(i);
}

int RobotModel::variable_index(const std::string& joint_name) const {
  const auto it = variable_index_.find(joint_name);
  return it == variable_index_.end() ? -1 : it->second;
}

int RobotModel::link_index(const std::string& link_name) const {
  for (size_t i = 0; i < links_.size(); ++i) {
    if (links_[i].name == link_name) return static_cast<int>(i);
  }
  return -1;
}

void RobotModel::apply(const JointPositions& updates, std::vector<double>& positions) const {
  if (positions.size() != variable_names_.size()) positions = zero_positions();
  for (const auto& [joint, value] : updates) {
    if (variable_index(joint) < 0) {
      std::string known;
      for (const auto& n : variable_names_) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("robot '" + name_ + "' has no movable joint '" + joint +
                                  "' (its movable joints: " + (known.empty() ? "none" : known) + ")");
    }
    if (!std::isfinite(value)) {
      throw std::invalid_argument("joint '" + joint + "' of robot '" + name_ + "': position is not a finite number");
    }
  }
  for (const auto& [joint, value] : updates) positions[variable_index(joint)] = value;
}

void RobotModel::check_limits(const JointPositions& positions) const {
  for (const auto& [name, value] : positions) {
    for (const auto& link : links_) {
      const Joint& j = link.joint;
      if (j.name != name || !j.limited) continue;
      // A hair of slack: limits written in degrees and converted round to the last digit.
      constexpr double kSlack = 1e-6;
      if (value < j.lower - kSlack || value > j.upper + kSlack) {
        std::ostringstream msg;
        msg << "joint '" << name << "' of robot '" << name_ << "': " << value << " is outside its limits [" << j.lower
            << ", " << j.upper << "] " << (j.type == JointType::kPrismatic ? "m" : "rad");
        throw std::invalid_argument(msg.str());
      }
    }
  }
}

std::vector<Pose> RobotModel::link_poses(const std::vector<double>& positions) const {
  if (positions.size() != variable_names_.size()) {
    throw std::invalid_argument("robot '" + name_ + "': expected " + std::to_string(variable_names_.size()) +
                                " joint positions, got " + std::to_string(positions.size()));
  }
  std::vector<Pose> poses(links_.size(), Pose::Identity());
  for (size_t i = 0; i < links_.size(); ++i) {
    const Link& link = links_[i];
    if (link.parent < 0) continue;
    const Joint& j = link.joint;
    Pose motion = Pose::Identity();
    if (j.variable >= 0) {
      const double q = j.multiplier * positions[j.variable] + j.offset;
      if (j.type == JointType::kPrismatic) {
        motion.translation() = q * j.axis;
      } else if (j.type != JointType::kFixed) {
        motion.linear() = Eigen::AngleAxisd(q, j.axis).toRotationMatrix();
      }
    }
    poses[i] = poses[link.parent] * j.T_parent_joint * motion;
  }
  return poses;
}

}  // namespace omniview::robot
