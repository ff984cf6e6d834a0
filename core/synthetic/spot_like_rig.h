// A rig of five cameras placed like Spot's body cameras: golden tests and spot-mock share
// it, so the mock's images and the golden references agree on one geometry.
#pragma once

#include "core/rig/rig.h"

namespace omniview::synthetic {

// Five greyscale-sized 640x480 pinholes (fx = fy = 330, principal point at the centre) in
// frame "body", named frontleft, frontright, left, right, back. As on Spot, the front pair
// cross (frontleft looks front-right) rolled by about +-90 deg, the right camera is mounted
// upside down, and all look 25-30 deg down. The ground is not part of the rig.
Rig spot_like_rig();

}  // namespace omniview::synthetic
