// A GetImage for the cameras some view needs: the request (formats with fallbacks for
// greyscale and colour robots) and the response checked image by image.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "bosdyn/api/image_service.grpc.pb.h"
#include "core/camera/camera.h"
#include "server/source/frame_set.h"
#include "spot_adapter/client/robot_session.h"
#include "spot_adapter/convert/frame_tree.h"
#include "spot_adapter/source/spot_settings.h"

namespace omniview::spot {

// A robot image source the Spot source pulls, and how it asks for it.
struct CameraSlot {
  std::string source;  // the robot's name, e.g. frontleft_fisheye_image
  Camera camera;       // named after its sensor frame; model and size from the robot
  // What to request; switched to PIXEL_FORMAT_UNKNOWN (the camera's own) when a robot
  // refuses the preferred format and ignores the fallback list.
  bosdyn::api::Image::PixelFormat pixel_format = bosdyn::api::Image::PIXEL_FORMAT_GREYSCALE_U8;
  // The robot's depth registered to this camera ("frontleft_depth_in_visual_frame"); empty:
  // the robot lists none.
  std::string depth_source;
};

// One camera's depth as points in its optical frame (depth_from_response.h).
struct DepthPointsOf {
  size_t slot = 0;
  std::vector<Eigen::Vector3f> points;
};

struct ImageSet {
  std::vector<cv::Mat> images;          // one per slot; empty where not wanted or bad
  std::vector<EncodedImage> encoded;    // one per slot
  std::vector<FrameEdge> edges;         // every response's frame tree, merged
  std::chrono::system_clock::time_point capture_time;  // robot clock, unless the robot sent none
  bool robot_time = false;              // capture_time is the robot's acquisition time
  size_t good = 0;                      // usable images
  std::vector<std::string> problems;    // one line per bad image, for health and the log
  std::vector<DepthPointsOf> depth;     // the depth asked for with the images
  std::vector<std::string> depth_problems;  // one line per bad depth image (the images still count)
};

// The request for `wanted` (slot indices), then the depth of `depth` (slots with a
// depth_source): one call, so the images are hardware-synchronised.
bosdyn::api::GetImageRequest image_request(const RobotSession& session, const SpotSettings& settings,
                                           const std::vector<CameraSlot>& slots, const std::vector<size_t>& wanted,
                                           const std::vector<size_t>& depth = {});

// The answer to image_request(), checked image by image: bad single images end up in
// ImageSet::problems; a response that is unusable as a whole (a header error, the wrong
// number of images) throws SpotError. A camera that refuses its pixel format is switched
// to the camera's own (`slots`) for the next request.
ImageSet images_from_response(const bosdyn::api::GetImageRequest& request, const bosdyn::api::GetImageResponse& response,
                              std::vector<CameraSlot>& slots, const std::vector<size_t>& wanted,
                              const std::vector<size_t>& depth = {});

}  // namespace omniview::spot
