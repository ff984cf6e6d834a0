// The joint positions one source's robot overlay draws, in layers, each over the one
// before: the URDF's zeros, the config's fixed `joints`, positions set through the API
// (SetJointPositions: robots whose source reports none), and the source's own report (Spot's
// robot state). A joint the source reports always shows as reported.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "server/pipeline/robot_layer.h"

namespace omniview {

using JointMap = std::map<std::string, double>;

// One movable joint of a robot model as GetJointPositions reports it.
struct JointReport {
  enum class Origin { kUrdfZero, kConfig, kApi, kSource };  // which layer set the position
  std::string name;
  double position = 0;
  std::string unit = "rad";  // or "m" (prismatic)
  Origin origin = Origin::kUrdfZero;
};

struct JointsReport {
  std::string source, robot;        // the robot: the URDF's name
  std::vector<JointReport> joints;  // every movable joint, in URDF order
};

class RobotJoints {
 public:
  explicit RobotJoints(std::shared_ptr<const RobotModelSetup> setup);

  // Merges `updates` into the API layer (after forgetting it when `clear`). Throws PipelineError
  // INVALID_ARGUMENT naming a joint the model does not have (and the ones it has) or a
  // value that is not a finite number; nothing changes then.
  void set(const JointMap& updates, bool clear);

  // Every movable joint of the model with the source's latest report `live` (null: none)
  // over the other layers. Returns the same pointer while nothing changed, so the views'
  // overlays can tell "re-render" from "reuse the last layer" by comparing pointers.
  // Joints the model does not know (an arm a URDF of the legs lacks) are left out.
  std::shared_ptr<const JointMap> effective(const std::shared_ptr<const JointMap>& live);

  // Every joint with its position and where that comes from (GetJointPositions).
  JointsReport describe(const std::string& source) const;

 private:
  const std::shared_ptr<const RobotModelSetup> setup_;
  mutable std::mutex mutex_;
  JointMap api_;
  uint64_t api_version_ = 0;
  std::shared_ptr<const JointMap> live_;      // the last report seen
  std::shared_ptr<const JointMap> merged_;    // cache of effective()
  uint64_t merged_api_version_ = ~0ULL;
  std::shared_ptr<const JointMap> merged_live_;
};

}  // namespace omniview
