#include "core/cloud/trajectory.h"

#include <algorithm>
#include <stdexcept>

#include <Eigen/Geometry>

namespace omniview {

void Trajectory::add(Time t, const Pose& T_fixed_body) {
  if (!T_fixed_body.matrix().allFinite()) throw std::invalid_argument("Trajectory::add: pose is not finite");
  auto it = std::lower_bound(samples_.begin(), samples_.end(), t, [](const Sample& s, Time x) { return s.t < x; });
  if (it != samples_.end() && it->t == t) {
    it->pose = T_fixed_body;
  } else {
    samples_.insert(it, Sample{t, T_fixed_body});
  }
  const Time oldest = samples_.back().t - window_;
  while (samples_.size() > 2 && samples_.front().t < oldest) samples_.pop_front();
}

std::optional<Pose> Trajectory::at(Time t) const {
  if (samples_.empty()) return std::nullopt;
  if (t <= samples_.front().t) return samples_.front().pose;
  if (t >= samples_.back().t) return samples_.back().pose;
  const auto hi = std::lower_bound(samples_.begin(), samples_.end(), t, [](const Sample& s, Time x) { return s.t < x; });
  const auto lo = hi - 1;
  const double span = std::chrono::duration<double>(hi->t - lo->t).count();
  const double a = span > 0 ? std::chrono::duration<double>(t - lo->t).count() / span : 0.0;
  const Eigen::Quaterniond q0(lo->pose.linear()), q1(hi->pose.linear());
  Pose out = Pose::Identity();
  out.linear() = q0.slerp(a, q1).normalized().toRotationMatrix();
  out.translation() = (1 - a) * lo->pose.translation() + a * hi->pose.translation();
  return out;
}

Pose Trajectory::relative(Time a, Time b) const {
  if (samples_.empty() || a == b) return Pose::Identity();
  return at(a)->inverse() * *at(b);
}

}  // namespace omniview
