// The robot's motion for time-synchronised cloud colouring: `body` in Spot's `odom` frame
// from each image set's frame-tree snapshot. odom drifts slowly but never jumps (vision
// may, when the robot corrects it), which is what matters over the ~0.1 s between a lidar
// sweep and the images that colour it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "spot_adapter/convert/frame_tree.h"

namespace omniview::spot {

inline constexpr const char* kOdomFrame = "odom";

// T_fixed_body from a snapshot's edges (each child's pose in its parent); nullopt when the
// two frames are not connected in it.
std::optional<Pose> pose_in_snapshot(const std::vector<FrameEdge>& edges, const std::string& fixed,
                                     const std::string& body);

}  // namespace omniview::spot
