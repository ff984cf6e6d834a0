// A camera rig: calibrated cameras and the frames they hang from.
//
// Each camera is also a frame (named like the camera) in `frames`, linked to its parent
// frame by T_parent_cam, so a view posed in any connected frame can find every camera.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/camera/camera.h"
#include "core/geometry/frame_graph.h"

namespace omniview {

class Rig {
 public:
  explicit Rig(std::string default_frame = "base_link") : default_frame_(std::move(default_frame)) {}

  // Frame that views use when they name none, and cameras hang from by default.
  const std::string& default_frame() const { return default_frame_; }

  // Adds `camera` and its frame link. Throws on a duplicate name (another camera, or a
  // frame that already has a parent), a mask of the wrong size or type, or an image size
  // < 2 pixels.
  void add_camera(Camera camera);
  // Adds a frame; throws if `child` is a camera or already has a parent. Live updates of
  // an existing link go through frames().set_parent().
  void add_frame(const std::string& child, const std::string& parent, const Pose& T_parent_child);

  const std::vector<Camera>& cameras() const { return cameras_; }
  const Camera* find(const std::string& name) const;
  const FrameGraph& frames() const { return frames_; }
  FrameGraph& frames() { return frames_; }

  // The frames connected to default_frame() (itself first): those a camera or a view can
  // be posed in.
  std::vector<std::string> known_frames() const;

  // Pose of camera `index`'s optical frame in `frame` (T_frame_cam).
  Pose camera_pose(const std::string& frame, size_t index) const;

 private:
  std::string default_frame_;
  FrameGraph frames_;
  std::vector<Camera> cameras_;
};

// Our rig YAML (see config/examples/dual_fisheye/rig.yaml for a commented example).
// Relative mask paths are resolved against the file's folder. Throws ConfigError naming
// file, line and key.
Rig load_rig_yaml(const std::string& path);

// Our rig YAML is strict: unknown keys are errors, and every camera and frame must connect
// to the rig's frame (an unknown `parent` is reported at load, listing the known frames).

// A kalibr camchain.yaml (cam0, cam1, ... with T_cn_cnm1 chains). Cameras are named after
// their keys (cam0, ...); cam0's optical frame sits at T_frame_cam0 in `frame`. Keys of a
// camera entry that we do not use (rostopic, T_cam_imu, cam_overlaps, ... which kalibr
// versions add and vary) are ignored.
Rig load_kalibr_camchain(const std::string& path, const std::string& frame, const Pose& T_frame_cam0);

// The same from already-parsed YAML (tests, fuzzing, configs that embed a rig); masks are
// resolved against `folder`.
class YamlReader;
Rig parse_rig_yaml(const YamlReader& reader, const std::string& folder);
Rig parse_kalibr_camchain(const YamlReader& reader, const std::string& frame, const Pose& T_frame_cam0);

// Whether `reader` holds a kalibr camchain rather than our rig YAML (a top-level cam0).
bool is_kalibr_camchain(const YamlReader& reader);

// Either format, told apart by content (a camchain has top-level cam0).
Rig load_rig(const std::string& path, const std::string& camchain_frame = "base_link",
             const Pose& camchain_T_frame_cam0 = Pose::Identity());

// `rig` in our rig YAML schema, which parse_rig_yaml reads back exactly (poses as 4x4
// T_parent_cam / T_parent_frame matrices at full precision). Masks are not embedded.
std::string rig_to_yaml(const Rig& rig);
// Writes rig_to_yaml(rig) to `path`, plus each camera's mask as <camera>_mask.png beside
// it (referenced as `mask:`). Throws std::runtime_error naming the file on failure.
void save_rig_yaml(const Rig& rig, const std::string& path);

}  // namespace omniview
