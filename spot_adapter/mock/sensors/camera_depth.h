// The body cameras' depth images, as Spot's `<camera>_depth_in_visual_frame` sources give
// them: registered to the visual camera (same size, intrinsics and pose), each pixel the
// distance along the optical axis in millimetres (PIXEL_FORMAT_DEPTH_U16, little-endian,
// depth_scale 1000), 0 where nothing was measured: beyond the stereo cameras' range, or
// nothing there. Rendered from the same scene as the pictures and the lidar, so the three
// agree; each camera's on its first request only (most clients never ask, and ray casting
// is the mock's start-up cost: a camera takes seconds under the sanitizers) — unless the
// mock keeps a render cache: then all are read from it, or rendered and stored, at start,
// so no GetImage waits for a render (under AddressSanitizer on a 2-core CI machine the first
// depth request took longer than the daemon's 2 s deadline, again and again, for ~12 s, in
// every test that watched a depth view).
#pragma once

#include <mutex>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/rig/rig.h"
#include "spot_adapter/mock/world/mock_scene.h"

namespace omniview::spot_mock {

inline constexpr double kDepthScale = 1000;   // raw value per metre (mm)
inline constexpr double kDepthRangeM = 4.0;   // Spot's body stereo cameras see about 4 m

// Camera `index` of `rig`'s depth (CV_16UC1, mm along its optical axis), the scene in
// `world_frame`; 0 beyond `range_m` or where the ray hits nothing.
cv::Mat render_depth_mm(const synthetic::Scene& scene, const Rig& rig, size_t index, const std::string& world_frame,
                        double range_m = kDepthRangeM);

class CameraDepths {
 public:
  // `render_cache`: a folder as MockRobotConfig's (empty: none, render on request).
  CameraDepths(SceneKind scene, const Rig& rig, const std::string& render_cache = "");

  // Camera `camera`'s depth image as the wire carries it: rows of little-endian uint16.
  // Thread-safe; the reference stays valid for the object's lifetime.
  const std::string& raw(size_t camera);

 private:
  SceneKind scene_;
  const Rig& rig_;
  std::mutex mutex_;  // one render at a time: a mock's depth clients are few
  std::vector<std::string> raw_;  // sized once: references to its strings stay valid
  std::vector<bool> rendered_;

  std::string render(const synthetic::Scene& world, size_t camera) const;  // the wire bytes
};

}  // namespace omniview::spot_mock
