// The robot drawn into a source's pinhole views (`robot_models` in the config, views with
// `overlay: true`): from exactly the view's camera, with the robot's live joint angles
// when the source reports them, re-rendered only when something it shows has changed.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <opencv2/core/mat.hpp>

#include "core/rig/rig.h"
#include "core/robot/model/robot_model.h"
#include "core/robot/overlay/robot_overlay.h"
#include "core/view/view_spec.h"

namespace omniview {

struct RobotModelSetup {
  std::shared_ptr<const robot::RobotModel> model;
  std::string frame;                   // rig frame of the URDF's root link (empty: the rig's own)
  std::map<std::string, double> fixed_joints;  // the config's positions (checked against the model)
  robot::OverlayStyle style;
};

// One view's robot layer. Thread-safe (a view renders from one thread at a time, but a
// snapshot and a stream may meet).
class ViewOverlay {
 public:
  explicit ViewOverlay(std::shared_ptr<const RobotModelSetup> setup);

  // Draws the robot into `image` at `spec.overlay_opacity`; a grey image becomes BGR first
  // so the robot keeps its colours. `joints`: every joint's position (RobotJoints::effective;
  // a new pointer means something moved); null keeps the last ones. Does nothing when the
  // rig does not connect the model's frame and the view's.
  void draw(cv::Mat& image, const ViewSpec& spec, const Rig& rig,
            const std::shared_ptr<const std::map<std::string, double>>& joints);

  int render_count() const;

 private:
  std::shared_ptr<const RobotModelSetup> setup_;
  mutable std::mutex mutex_;
  robot::RobotOverlay overlay_;
  std::shared_ptr<const std::map<std::string, double>> last_joints_;
  bool warned_missing_frame_ = false;
};

}  // namespace omniview
