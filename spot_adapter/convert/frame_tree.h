// A robot's FrameTreeSnapshot as transforms omniview can use. Spot's tree is keyed by
// child frame; the root (usually `body`) has an empty parent.
#pragma once

#include <string>
#include <vector>

#include "bosdyn/api/geometry.pb.h"
#include "core/geometry/pose.h"

namespace omniview::spot {

struct FrameEdge {
  std::string child;
  std::string parent;
  Pose T_parent_child;
};

// Throws SpotError(kProtocol) naming `what` and the frame for a non-finite position or a
// rotation that is not a (roughly) unit quaternion; renormalises small rounding.
Pose to_pose(const bosdyn::api::SE3Pose& pose, const std::string& what);

// Every edge of `snapshot` but its roots, in a stable (name) order.
std::vector<FrameEdge> frame_edges(const bosdyn::api::FrameTreeSnapshot& snapshot, const std::string& what);

}  // namespace omniview::spot
