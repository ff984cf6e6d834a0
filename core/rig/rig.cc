#include "core/rig/rig.h"

#include <stdexcept>

namespace omniview {

void Rig::add_camera(Camera camera) {
  if (camera.name.empty()) throw std::invalid_argument("camera name must not be empty");
  if (find(camera.name)) throw std::invalid_argument("camera '" + camera.name + "' is defined twice");
  if (camera.width < 2 || camera.height < 2 || camera.width > 65535 || camera.height > 65535) {
    throw std::invalid_argument("camera '" + camera.name + "': resolution " + std::to_string(camera.width) +
                                "x" + std::to_string(camera.height) + " is not a usable image size");
  }
  if (!camera.mask.empty()) {
    if (camera.mask.type() != CV_8UC1 || camera.mask.cols != camera.width || camera.mask.rows != camera.height) {
      throw std::invalid_argument("camera '" + camera.name + "': mask must be 8-bit greyscale of " +
                                  std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                                  ", got " + std::to_string(camera.mask.cols) + "x" +
                                  std::to_string(camera.mask.rows) + " with " +
                                  std::to_string(camera.mask.channels()) + " channel(s)");
    }
  }
  if (camera.fov_deg < 0 || camera.fov_deg > 360) {
    throw std::invalid_argument("camera '" + camera.name + "': fov_deg must be in [0, 360]");
  }
  if (camera.parent_frame.empty()) camera.parent_frame = default_frame_;
  // set_parent() would silently re-hang an existing frame (and everything under it) from
  // this camera's parent. A frame only named as a parent so far is fine: it gets its link.
  if (const auto parent = frames_.parent_of(camera.name)) {
    throw std::invalid_argument("camera '" + camera.name + "': the rig already has a frame of that name (under '" +
                                *parent + "')");
  }
  frames_.set_parent(camera.name, camera.parent_frame, camera.T_parent_cam);
  cameras_.push_back(std::move(camera));
}

void Rig::add_frame(const std::string& child, const std::string& parent, const Pose& T_parent_child) {
  if (find(child)) throw std::invalid_argument("frame '" + child + "' is a camera's name");
  if (const auto old_parent = frames_.parent_of(child)) {
    throw std::invalid_argument("frame '" + child + "' is defined twice (already under '" + *old_parent + "')");
  }
  frames_.set_parent(child, parent, T_parent_child);
}

const Camera* Rig::find(const std::string& name) const {
  for (const auto& c : cameras_) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::vector<std::string> Rig::known_frames() const {
  std::vector<std::string> known{default_frame_};
  for (const auto& frame : frames_.frames()) {
    if (frame != default_frame_ && frames_.try_lookup(default_frame_, frame)) known.push_back(frame);
  }
  return known;
}

Pose Rig::camera_pose(const std::string& frame, size_t index) const {
  return frames_.lookup(frame, cameras_.at(index).name);
}

}  // namespace omniview
