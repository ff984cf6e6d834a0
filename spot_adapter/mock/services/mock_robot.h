// Everything the services share: the robot's pictures and scan (made once at start-up,
// read-only after), and the state that changes at run time (tokens, faults, counters,
// joints; each locks itself, as the services run on gRPC's threads).
#pragma once

#include <chrono>
#include <string>

#include "core/rig/rig.h"
#include "spot_adapter/mock/auth/token_store.h"
#include "spot_adapter/mock/sensors/camera_depth.h"
#include "spot_adapter/mock/sensors/camera_images.h"
#include "spot_adapter/mock/sensors/lidar_scan.h"
#include "spot_adapter/mock/state/counters.h"
#include "spot_adapter/mock/state/faults.h"
#include "spot_adapter/mock/state/joint_angles.h"
#include "spot_adapter/mock/world/mock_scene.h"

namespace omniview::spot_mock {

struct MockRobotConfig {
  SceneKind scene = SceneKind::kRoom;
  bool colour = false;  // an RGB robot (newer Spots) instead of greyscale cameras
  int supersample = 2;  // rays per pixel along each axis when rendering
  // A folder of pictures and depth images rendered by earlier starts (sensors/render_cache.h);
  // empty: none.
  std::string render_cache;
  Credentials credentials;
  TokenStore::Policy token_policy;
  FaultSettings faults;
};

struct MockRobot {
  explicit MockRobot(const MockRobotConfig& config);  // renders the cameras and the scan

  const Rig rig;  // mock_rig(): the cameras' intrinsics
  CameraImages cameras;
  CameraDepths depths;  // from the render cache at start, else rendered on first request
  const LidarScan lidar;
  TokenStore tokens;
  Faults faults;
  Counters counters;
  JointAngles joints;
  const std::chrono::system_clock::time_point started = std::chrono::system_clock::now();
};

}  // namespace omniview::spot_mock
