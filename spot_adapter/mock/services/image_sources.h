// How the mock's body cameras describe themselves (bosdyn.api.ImageSource): pinhole
// intrinsics, size and formats, as Spot's rectified body cameras report them.
#pragma once

#include "bosdyn/api/image.pb.h"
#include "core/camera/camera.h"
#include "spot_adapter/mock/world/mock_scene.h"

namespace omniview::spot_mock {

bosdyn::api::ImageSource describe_source(const MockCamera& mock_camera, const Camera& camera, bool colour_robot);

}  // namespace omniview::spot_mock
