// Points on the robot's own body: the URDF model posed at the current joint positions,
// each visual's box (in its link's frame) grown by a margin. A lidar on the robot sees its
// legs and arm; those points must not be coloured (the cameras see the leg, or what is
// behind it) nor drawn as obstacles.
//
// In its own library (omniview_cloud_robot) so that colouring does not pull in the robot
// model's urdfdom/assimp/Mesa dependencies.
#pragma once

#include <vector>

#include "core/cloud/point_cloud.h"
#include "core/robot/model/robot_model.h"

namespace omniview {

class SelfFilter {
 public:
  // `margin_m` grows every box on all sides: calibration error, joint-reading lag and the
  // lidar's range noise (a VLP-16's is +-3 cm) put true body points just outside the model.
  SelfFilter(const robot::RobotModel& model, double margin_m = 0.05);

  // Sets cloud_flags::kSelf on the points inside the body at `positions` (the model's
  // variable vector), and returns how many. T_root_cloud: the cloud's frame in the model's
  // root link frame (the same frame when they are one).
  size_t mark(PointCloud& cloud, const std::vector<double>& positions, const Pose& T_root_cloud) const;

  double margin() const { return margin_; }

 private:
  struct Box {
    int link = 0;
    Eigen::Vector3f lo, hi;  // in the link's frame, margin included
  };
  const robot::RobotModel& model_;
  double margin_;
  std::vector<Box> boxes_;
};

}  // namespace omniview
