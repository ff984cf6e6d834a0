// A robot's kinematic tree and visual geometry, and its forward kinematics.
//
// Links are stored parents first, so one pass over them computes every link's pose in the
// root link's frame (the robot's base frame, REP-103). Joint positions are radians for
// revolute and continuous joints, metres for prismatic ones; limits are checked only on
// request (check_limits), since a robot's report is drawn as it is.
// Floating and planar joints are held at their origin (nothing reports their state here).
// Immutable once built: share one model between views and threads.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/geometry/pose.h"
#include "core/robot/model/triangle_mesh.h"

namespace omniview::robot {

// Joint name -> position. Updates may name any subset of the movable joints.
using JointPositions = std::map<std::string, double>;

enum class JointType { kFixed, kRevolute, kContinuous, kPrismatic };

struct Joint {
  std::string name;
  JointType type = JointType::kFixed;
  Pose T_parent_joint = Pose::Identity();  // joint frame in the parent link at position 0
  Vec3 axis = Vec3::UnitX();               // unit, in the joint frame
  int variable = -1;                       // index into the position vector; -1 when fixed
  double multiplier = 1, offset = 0;       // mimic: q = multiplier * q[variable] + offset
  bool limited = false;                    // revolute and prismatic joints with limits
  double lower = 0, upper = 0;             // rad or m
};

struct Link {
  std::string name;
  int parent = -1;  // index of the parent link; -1 for the root
  Joint joint;      // the joint from the parent (unused for the root)
};

// Geometry attached to a link, already in the link's frame (visual origin and scale applied).
struct Visual {
  int link = 0;
  TriangleMesh mesh;
};

class RobotModel {
 public:
  RobotModel(std::string name, std::vector<Link> links, std::vector<Visual> visuals,
             std::vector<std::string> variable_names);

  const std::string& name() const { return name_; }
  const std::vector<Link>& links() const { return links_; }
  const std::vector<Visual>& visuals() const { return visuals_; }
  // Names of the independent joint variables (movable, non-mimic joints), in vector order.
  const std::vector<std::string>& variable_names() const { return variable_names_; }
  int variable_index(const std::string& joint_name) const;  // -1 when unknown
  int link_index(const std::string& link_name) const;       // -1 when unknown

  // All variables at zero.
  std::vector<double> zero_positions() const { return std::vector<double>(variable_names_.size(), 0.0); }
  // Writes `updates` into `positions`. Throws std::invalid_argument for a name that is not a
  // movable joint of this robot (listing the ones it has) or a non-finite value, leaving
  // `positions` unchanged.
  void apply(const JointPositions& updates, std::vector<double>& positions) const;
  // Throws std::invalid_argument naming the joint and its URDF limits for a position
  // outside them (for positions people give: a robot's own report is drawn as it is).
  void check_limits(const JointPositions& positions) const;
  // Pose of every link (by index) in the root link's frame.
  std::vector<Pose> link_poses(const std::vector<double>& positions) const;

 private:
  std::string name_;
  std::vector<Link> links_;
  std::vector<Visual> visuals_;
  std::vector<std::string> variable_names_;
  std::map<std::string, int> variable_index_;
};

}  // namespace omniview::robot
