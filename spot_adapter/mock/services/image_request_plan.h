// How spot-mock answers one ImageRequest, decided before any bytes are touched: which
// camera, the status Spot's image service would give, and the encoding it would send.
#pragma once

#include <optional>

#include "bosdyn/api/image.pb.h"
#include "spot_adapter/mock/sensors/camera_images.h"

namespace omniview::spot_mock {

inline constexpr int kDefaultJpegQuality = 75;  // what the SDKs ask for by default

struct ImagePlan {
  bosdyn::api::ImageResponse::Status status = bosdyn::api::ImageResponse::STATUS_OK;
  std::optional<size_t> camera;  // index in mock_cameras(), if the name is known
  bool depth = false;            // the camera's "_depth_in_visual_frame" source
  Encoding encoding = Encoding::kJpeg;
  bosdyn::api::Image::PixelFormat pixel_format = bosdyn::api::Image::PIXEL_FORMAT_GREYSCALE_U8;
  int quality = kDefaultJpegQuality;
};

// As Spot's body cameras do: an unknown name is STATUS_UNKNOWN_CAMERA; resize_ratio must be
// 0 or 1; FORMAT_UNKNOWN means JPEG and RLE is not offered; the pixel format is the first of
// the requested one and its fallbacks that the robot can give (UNKNOWN: its own; GREYSCALE_U8
// always; RGB_U8 only on a colour robot). A depth source is RAW DEPTH_U16 only (UNKNOWN
// asks for those too).
ImagePlan plan_image(const bosdyn::api::ImageRequest& request, bool colour_robot);

}  // namespace omniview::spot_mock
