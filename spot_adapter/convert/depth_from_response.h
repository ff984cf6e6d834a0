// A depth camera's ImageResponse as measured points for depth-aware views: Spot's
// `<camera>_depth_in_visual_frame` sources are registered to the visual camera (the same
// size and intrinsics), PIXEL_FORMAT_DEPTH_U16 as RAW little-endian values, metres = value
// / ImageSource.depth_scale along the optical axis, 0 where nothing was measured. A response
// is outside data: status, format, size, data length and scale are checked here.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "bosdyn/api/image.pb.h"
#include "core/camera/camera.h"

namespace omniview::spot {

// The robot's depth source for visual source `image_source` ("frontleft_fisheye_image" ->
// "frontleft_depth_in_visual_frame"), by Spot's naming.
std::string depth_source_for(const std::string& image_source);

// Points in `camera`'s optical frame from every `step`-th pixel (each way) that holds a
// depth; depths beyond `max_range_m` are dropped (stereo depth that far is noise). Throws
// SpotError(kProtocol) naming `camera` for a response that is not a usable depth image of
// the camera's size.
std::vector<Eigen::Vector3f> points_from_depth_response(const bosdyn::api::ImageResponse& response, const Camera& camera,
                                                        int step, double max_range_m = 10);

}  // namespace omniview::spot
