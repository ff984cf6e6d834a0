// The lidar's point cloud: rays from the sensor, spread in rings like a 16-beam Velodyne,
// cast against the scene once (the scene is static).
#pragma once

#include <string>

#include "core/synthetic/scene.h"

namespace omniview::spot_mock {

struct LidarScan {
  int num_points = 0;
  std::string xyz_32f;  // num_points x (x, y, z) float32 little-endian, in the sensor frame
};

// Rays that hit nothing within kLidarMaxRangeM give no point. `T_world_lidar` places the
// sensor in the scene's frame.
LidarScan scan_scene(const synthetic::Scene& scene, const Pose& T_world_lidar);

}  // namespace omniview::spot_mock
