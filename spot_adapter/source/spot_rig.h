// The rig a Spot source delivers: the robot's cameras (calibration from ListImageSources)
// hung in the robot's frame tree, rooted at `body`, plus `footprint`: body's point on the
// ground, gravity-aligned, so a bird's-eye view posed there looks at the ground at the
// right height however the robot stands.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/rig/rig.h"
#include "spot_adapter/convert/frame_tree.h"

namespace omniview::spot {

inline constexpr const char* kBodyFrame = "body";
inline constexpr const char* kFootprintFrame = "footprint";

// Before the robot has answered: `body` and the standard frames Spot has (vision, odom,
// gpe, flat_body) plus footprint, without cameras, so configured views can be created and
// get their cameras once the robot is there.
std::shared_ptr<const Rig> placeholder_rig();

// `cameras` are named after their sensor frames (e.g. frontleft_fisheye) and carry model
// and size; `tree` maps child -> edge. Throws SpotError(kProtocol) when a camera's frame
// is missing from the tree or the tree is not one.
std::shared_ptr<const Rig> build_spot_rig(const std::vector<Camera>& cameras,
                                          const std::map<std::string, FrameEdge>& tree);

// Whether two edges differ by more than a millimetre or a twentieth of a degree: less is
// noise in the robot's estimates and not worth rebuilding every view's map for.
bool edge_moved(const FrameEdge& a, const FrameEdge& b);

}  // namespace omniview::spot
