// A spinning 16-laser lidar (Velodyne VLP-16 geometry: elevations -15..+15 deg every 2 deg,
// one firing of all lasers per azimuth column) ray-cast in a synthetic scene. Tests,
// benchmarks, the mock robot and packet generators use it as their lidar.
#pragma once

#include <chrono>
#include <functional>
#include <vector>

#include "core/cloud/point_cloud.h"
#include "core/synthetic/scene.h"

namespace omniview::synthetic {

struct LidarScanOptions {
  int columns = 1800;          // azimuth steps per rotation (0.2 deg at 10 Hz)
  double rotation_s = 0.1;     // one rotation's duration (10 Hz)
  double min_range = 0.4;      // closer returns are dropped (the VLP-16's blind range)
  double max_range = 100;      // farther or no return: dropped
  bool keep_colour = false;    // fill rgb with the scene's colour at each hit (ground truth)
};

// One rotation, starting at azimuth 0 (the lidar's +x) and turning counter-clockwise. The
// lidar's pose in the scene's world at time t after `stamp` (seconds) is T_world_lidar(t);
// each point is given in the lidar's frame as it was when that point was measured, with
// its time and ring (0 = lowest laser) set, like a real scan.
PointCloud scan_vlp16(const Scene& scene, const std::function<Pose(double)>& T_world_lidar, const std::string& frame,
                      std::chrono::system_clock::time_point stamp, const LidarScanOptions& options = {});

// The same from a lidar that stands still at T_world_lidar.
PointCloud scan_vlp16(const Scene& scene, const Pose& T_world_lidar, const std::string& frame,
                      std::chrono::system_clock::time_point stamp, const LidarScanOptions& options = {});

// VLP-16 laser elevation (degrees) by ring, lowest first.
inline double vlp16_elevation_deg(int ring) { return -15.0 + 2.0 * ring; }

}  // namespace omniview::synthetic
