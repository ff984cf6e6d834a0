// How the mock's body cameras describe themselves (bosdyn.api.ImageSource): pinhole
// intrinsics, size and formats, as Spot's rectified body cameras report them.
#pragma once

#include "bosdyn/api/image.pb.h"
#include "core/camera/camera.h"
#include "spot_adapter/mock/world/mock_scene.h"

namespace omniview::spot_mock {

bosdyn::api::ImageSource describe_source(const MockCamera& mock_camera, const Camera& camera, bool colour_robot);

// The camera's depth registered to it: "<mount>_depth_in_visual_frame", the same size and
// intrinsics, IMAGE_TYPE_DEPTH, DEPTH_U16 as RAW only, depth_scale 1000 (sensors/camera_depth.h).
std::string depth_source_name(const MockCamera& mock_camera);
bosdyn::api::ImageSource describe_depth_source(const MockCamera& mock_camera, const Camera& camera);

}  // namespace omniview::spot_mock
