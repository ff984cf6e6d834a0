// What spot-mock's robot sees and how it is built: the scenes, the body cameras, the frame
// tree and the lidar. No gRPC here, so tests can build the same world and compare.
//
// World frame "vision": z = 0 is the ground; the robot stands level over its origin, facing +x.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/rig/rig.h"
#include "core/synthetic/scene.h"

namespace omniview::spot_mock {

inline constexpr double kBodyHeightM = 0.52;  // the body frame's height above the ground
inline constexpr int kImageCols = 640;
inline constexpr int kImageRows = 480;
inline constexpr const char* kBodyFrame = "body";
inline constexpr const char* kWorldFrame = "vision";
inline constexpr const char* kLidarFrame = "eap";
inline constexpr const char* kLidarSource = "velodyne-point-cloud";
inline constexpr double kTestWallX = 3.0;  // the test scene's wall: x = 3 m in "vision"

enum class SceneKind {
  kRoom,  // a furnished room with muted, lit materials (demos)
  kTest,  // bare Scene::texture() on the floor z = 0 and on the wall x = kTestWallX above it
};
std::optional<SceneKind> parse_scene_kind(std::string_view name);  // "room" or "test"
const char* to_string(SceneKind kind);

// The scene in frame kWorldFrame.
synthetic::Scene make_scene(SceneKind kind);

struct MockCamera {
  std::string source;        // image source name, e.g. "frontleft_fisheye_image"
  std::string mount_frame;   // "frontleft": under body, x along the optical axis (REP-103)
  std::string sensor_frame;  // "frontleft_fisheye": under the mount, optical (z axis, x right, y down)
};
// The five body cameras, in the order of mock_rig()'s cameras.
const std::vector<MockCamera>& mock_cameras();

// synthetic::spot_like_rig() (cameras named like their mount frames) with kWorldFrame
// added, so render_camera(scene, mock_rig(), i, kWorldFrame) gives camera i's image.
Rig mock_rig();

// One edge of the frame tree: the pose of `child` in `parent` (empty parent: the root).
struct FrameEdge {
  std::string child, parent;
  Pose T_parent_child = Pose::Identity();
};
// body (root); vision, odom, gpe, flat_body, the lidar and every camera's mount frame under
// body; each camera's sensor frame under its mount.
std::vector<FrameEdge> mock_frame_tree();

// The lidar's rays: rings from -15 to +15 deg elevation, points evenly in azimuth.
inline constexpr int kLidarRings = 16;
inline constexpr int kLidarPointsPerRing = 900;
inline constexpr double kLidarMaxRangeM = 100;
Pose T_body_lidar();

// The twelve leg joints ("fl.hx", "fl.hy", "fl.kn", ..., "hr.kn") and their standing angles.
const std::vector<std::string>& joint_names();
double standing_angle(const std::string& joint);

}  // namespace omniview::spot_mock
