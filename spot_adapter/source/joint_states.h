// The robot's joint positions from its robot-state service, for the robot overlay.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "spot_adapter/client/robot_session.h"

namespace omniview::spot {

using JointMap = std::map<std::string, double>;

// GetRobotState on the directory's `robot-state` service: every joint with a position.
// Throws SpotError for a failed call or a robot without that service.
std::shared_ptr<const JointMap> get_joint_states(RobotSession& session);

}  // namespace omniview::spot
