#include "server/pipeline/robot_layer.h"

#include <iostream>

#include <opencv2/imgproc.hpp>

#include "core/robot/overlay/composite.h"
#include "core/robot/render/pinhole_camera.h"

namespace omniview {

ViewOverlay::ViewOverlay(std::shared_ptr<const RobotModelSetup> setup)
    : setup_(std::move(setup)), overlay_(setup_->model, setup_->style) {
  overlay_.set_joint_positions(setup_->fixed_joints);  // checked against the model at load
}

void ViewOverlay::draw(cv::Mat& image, const ViewSpec& spec, const Rig& rig,
                       const std::shared_ptr<const std::map<std::string, double>>& joints) {
  const std::string model_frame = setup_->frame.empty() ? rig.default_frame() : setup_->frame;
  const std::string view_frame = spec.frame.empty() ? rig.default_frame() : spec.frame;
  const auto T_model_frame = rig.frames().try_lookup(model_frame, view_frame);
  std::lock_guard lock(mutex_);
  if (!T_model_frame) {
    // Views render only once a source delivers images, so its rig is the real one: say
    // once why the robot is missing (a typo in robot_models[].frame) instead of nothing.
    if (!warned_missing_frame_) {
      std::string known;
      for (const auto& f : rig.known_frames()) known += (known.empty() ? "" : ", ") + f;
      std::cerr << "omniviewd: view '" << spec.name << "': robot overlay not drawn: frame '" << model_frame
                << "' (robot_models[].frame) is not connected to the view's frame '" << view_frame
                << "' in source '" << spec.source << "' (its frames: " << known << ")" << std::endl;
      warned_missing_frame_ = true;
    }
    return;
  }
  if (joints && joints != last_joints_) {
    overlay_.set_joint_positions(*joints);  // only the model's joints (RobotJoints filters)
    last_joints_ = joints;
  }
  const auto& layer =
      overlay_.layer(robot::pinhole_camera_of(spec), *T_model_frame * robot::T_frame_optical(spec));
  if (layer.bbox.empty()) return;
  if (image.channels() == 1) cv::cvtColor(image, image, cv::COLOR_GRAY2BGR);
  robot::composite(layer, image, spec.overlay_opacity);
}

int ViewOverlay::render_count() const {
  std::lock_guard lock(mutex_);
  return overlay_.render_count();
}

}  // namespace omniview
