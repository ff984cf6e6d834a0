#include "core/robot/overlay/robot_overlay.h"

#include <cmath>

namespace omniview::robot {

RobotOverlay::RobotOverlay(std::shared_ptr<const RobotModel> model, OverlayStyle style, ChangeThresholds thresholds)
    : model_(std::move(model)), style_(style), thresholds_(thresholds), positions_(model_->zero_positions()) {}

void RobotOverlay::set_joint_positions(const JointPositions& positions) { model_->apply(positions, positions_); }

void RobotOverlay::set_style(const OverlayStyle& style) {
  style_ = style;
  rendered_ = false;
}

bool RobotOverlay::needs_render(const PinholeCamera& camera, const Pose& T_robot_camera) const {
  if (!rendered_ || !(camera == last_camera_)) return true;
  for (size_t i = 0; i < positions_.size(); ++i) {
    if (std::abs(positions_[i] - last_positions_[i]) > thresholds_.joint) return true;
  }
  const Pose delta = last_T_robot_camera_.inverse() * T_robot_camera;
  if (delta.translation().norm() > thresholds_.translation) return true;
  return Eigen::AngleAxisd(delta.linear()).angle() > thresholds_.rotation;
}

const OverlayLayer& RobotOverlay::layer(const PinholeCamera& camera, const Pose& T_robot_camera) {
  if (!needs_render(camera, T_robot_camera)) return layer_;
  const std::vector<Pose> link_poses = model_->link_poses(positions_);
  std::vector<DrawItem> items;
  items.reserve(model_->visuals().size());
  const Vec3 camera_in_robot = T_robot_camera.translation();
  for (const auto& visual : model_->visuals()) {
    // A camera inside a part (a view placed in the body, where the robot's own cameras are)
    // sees out of it, not its inside walls filling the whole view.
    const Vec3 camera_in_mesh = link_poses[visual.link].inverse() * camera_in_robot;
    if (visual.mesh.box_contains(camera_in_mesh.cast<float>())) continue;
    items.push_back({&visual.mesh, link_poses[visual.link]});
  }
  layer_.bgra = renderer_.render(items, camera, T_robot_camera);
  layer_.bbox = alpha_bounding_box(layer_.bgra);
  add_outline(layer_, style_.outline_px, style_.outline_bgr);
  rendered_ = true;
  last_camera_ = camera;
  last_T_robot_camera_ = T_robot_camera;
  last_positions_ = positions_;
  ++render_count_;
  return layer_;
}

}  // namespace omniview::robot
