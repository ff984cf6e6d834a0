// A Spot point cloud (GetPointCloud's answer) as omniview's PointCloud: XYZ float32 in the
// sensor frame the source names, moved into the root of the cloud's own frame-tree
// snapshot (Spot's `body`) with that snapshot, so it needs no other tree to be placed.
#pragma once

#include <chrono>

#include "bosdyn/api/point_cloud.pb.h"
#include "core/cloud/point_cloud.h"

namespace omniview::spot {

// `stamp`: the capture time on our clock (the caller converts the robot's acquisition time).
// Throws SpotError(kProtocol) naming `what` for an encoding other than XYZ_32F, a data size
// that does not match num_points, or a sensor frame missing from the snapshot.
PointCloud cloud_from_spot(const bosdyn::api::PointCloud& cloud, std::chrono::system_clock::time_point stamp,
                           const std::string& what);

// The robot's acquisition time of `cloud` (robot clock); epoch when it sent none.
std::chrono::system_clock::time_point cloud_acquisition_time(const bosdyn::api::PointCloud& cloud);

}  // namespace omniview::spot
