#include "spot_adapter/mock/state/joint_angles.h"

#include <cmath>
#include <stdexcept>

#include "spot_adapter/mock/world/mock_scene.h"

namespace omniview::spot_mock {

JointAngles::JointAngles() {
  for (const auto& name : joint_names()) angles_[name] = standing_angle(name);
}

std::map<std::string, double> JointAngles::get() const {
  std::lock_guard lock(mutex_);
  return angles_;
}

std::map<std::string, double> JointAngles::set(const std::map<std::string, double>& positions) {
  std::lock_guard lock(mutex_);
  for (const auto& [name, angle] : positions) {
    if (!angles_.count(name)) throw std::invalid_argument("unknown joint '" + name + "' (fl.hx ... hr.kn)");
    if (!std::isfinite(angle)) throw std::invalid_argument("joint '" + name + "' needs a finite angle");
  }
  for (const auto& [name, angle] : positions) angles_[name] = angle;
  return angles_;
}

}  // namespace omniview::spot_mock
