// A view's robot layer, re-rendered only when something it shows has changed.
//
// Inputs: the joint positions (set_joint_positions, any subset), the view's camera and the
// pose of its optical frame in the robot's base frame (which moves when the robot moves
// relative to a view given in another frame). layer() renders when any input differs from
// the inputs of the last render by more than the thresholds, and otherwise returns the
// last layer as is, so a frame in which nothing moved costs only the compositing.
// Comparing against the last *render* (not the last call) lets slow drift add up.
//
// Not thread-safe: one RobotOverlay per view, used by one thread at a time. The model is
// shared and immutable.
#pragma once

#include <memory>

#include "core/robot/model/robot_model.h"
#include "core/robot/overlay/overlay_layer.h"
#include "core/robot/render/offscreen_renderer.h"

namespace omniview::robot {

struct OverlayStyle {
  int outline_px = 0;                              // 0: no outline; 1-2 px reads well
  cv::Scalar outline_bgr = cv::Scalar(20, 20, 20);  // dark grey
};

// Smaller changes than these do not trigger a render: sub-pixel at robot scale.
struct ChangeThresholds {
  double joint = 1e-4;        // rad, or m for prismatic joints
  double translation = 1e-4;  // m
  double rotation = 1e-5;     // rad
};

class RobotOverlay {
 public:
  explicit RobotOverlay(std::shared_ptr<const RobotModel> model, OverlayStyle style = {},
                        ChangeThresholds thresholds = {});

  const RobotModel& model() const { return *model_; }

  // Partial update; throws std::invalid_argument (unknown joint, non-finite value) and then
  // changes nothing.
  void set_joint_positions(const JointPositions& positions);
  const std::vector<double>& joint_positions() const { return positions_; }

  void set_style(const OverlayStyle& style);

  // The layer for this camera; renders when needed (see above).
  const OverlayLayer& layer(const PinholeCamera& camera, const Pose& T_robot_camera);

  // How many times layer() has rendered (for tests and status).
  int render_count() const { return render_count_; }

 private:
  bool needs_render(const PinholeCamera& camera, const Pose& T_robot_camera) const;

  std::shared_ptr<const RobotModel> model_;
  OverlayStyle style_;
  ChangeThresholds thresholds_;
  OffscreenRenderer renderer_;
  std::vector<double> positions_;

  // Inputs of the last render; `rendered_` is false before the first and after set_style.
  bool rendered_ = false;
  PinholeCamera last_camera_;
  Pose last_T_robot_camera_ = Pose::Identity();
  std::vector<double> last_positions_;
  OverlayLayer layer_;
  int render_count_ = 0;
};

}  // namespace omniview::robot
