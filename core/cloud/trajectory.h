// The robot's motion over a short window: stamped poses of its body frame in a fixed frame
// (odometry, or a frame tree's "odom"/"vision" frame), so that a point measured at one time
// can be moved to where it was at another (a camera's capture time, a cloud's stamp).
#pragma once

#include <chrono>
#include <deque>
#include <optional>

#include "core/geometry/pose.h"

namespace omniview {

class Trajectory {
 public:
  using Time = std::chrono::system_clock::time_point;

  // `window`: how much history to keep, counted back from the newest sample.
  explicit Trajectory(std::chrono::milliseconds window = std::chrono::seconds(2)) : window_(window) {}

  // Adds T_fixed_body at `t`. Samples may come in any order; one at an existing time
  // replaces it. Throws std::invalid_argument for a non-finite pose.
  void add(Time t, const Pose& T_fixed_body);
  bool empty() const { return samples_.empty(); }
  size_t size() const { return samples_.size(); }

  // T_fixed_body at `t`: linear in translation, slerp in rotation between the samples
  // around it. Outside the samples' span the nearest end is held (the robot is assumed
  // still beyond what odometry reported). nullopt when empty.
  std::optional<Pose> at(Time t) const;

  // T_body(a)_body(b): the pose of the body at time b in the body frame at time a. Identity
  // when empty (no odometry: the robot is assumed still).
  Pose relative(Time a, Time b) const;

 private:
  struct Sample {
    Time t;
    Pose pose;
  };
  std::chrono::milliseconds window_;
  std::deque<Sample> samples_;  // by time
};

}  // namespace omniview
