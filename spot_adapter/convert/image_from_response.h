// One camera's ImageResponse as the image the pipeline takes: 8-bit greyscale or BGR, at
// the size the camera is calibrated for. Everything a robot (or a bad network) can get
// wrong is checked here, since a response is outside data: statuses, sizes that disagree
// with the data, corrupt JPEG, pixel formats we cannot show.
#pragma once

#include <string>

#include <opencv2/core/mat.hpp>

#include "bosdyn/api/image.pb.h"
#include "server/source/frame_set.h"

namespace omniview::spot {

struct DecodedImage {
  cv::Mat image;          // CV_8UC1 or CV_8UC3 (BGR)
  EncodedImage encoded;   // the robot's JPEG bytes (kept for recordings), or none for RAW
};

// Throws SpotError(kProtocol) with a message naming `camera` when the response is not a
// usable image of width x height.
DecodedImage decode_image_response(const bosdyn::api::ImageResponse& response, const std::string& camera,
                                   int width, int height);

}  // namespace omniview::spot
