#include "spot_adapter/mock/services/image_request_plan.h"

#include <algorithm>
#include <cmath>

#include "spot_adapter/mock/services/image_sources.h"
#include "spot_adapter/mock/world/mock_scene.h"

namespace omniview::spot_mock {
namespace {

using bosdyn::api::Image;
using bosdyn::api::ImageResponse;

std::optional<size_t> find_camera(const std::string& source, bool& depth) {
  for (size_t i = 0; i < mock_cameras().size(); ++i) {
    depth = source == depth_source_name(mock_cameras()[i]);
    if (mock_cameras()[i].source == source || depth) return i;
  }
  return std::nullopt;
}

// A depth source's answer: RAW DEPTH_U16, or the status Spot gives for anything else.
void plan_depth(const bosdyn::api::ImageRequest& request, ImagePlan& plan) {
  if (request.image_format() != Image::FORMAT_UNKNOWN && request.image_format() != Image::FORMAT_RAW) {
    plan.status = ImageResponse::STATUS_UNSUPPORTED_IMAGE_FORMAT_REQUESTED;
    return;
  }
  bool depth_format = request.pixel_format() == Image::PIXEL_FORMAT_UNKNOWN ||
                      request.pixel_format() == Image::PIXEL_FORMAT_DEPTH_U16;
  for (int i = 0; i < request.fallback_formats_size(); ++i) {
    depth_format = depth_format || request.fallback_formats(i) == Image::PIXEL_FORMAT_DEPTH_U16;
  }
  if (!depth_format) {
    plan.status = ImageResponse::STATUS_UNSUPPORTED_PIXEL_FORMAT_REQUESTED;
    return;
  }
  plan.encoding = Encoding::kRaw;
  plan.pixel_format = Image::PIXEL_FORMAT_DEPTH_U16;
}

// The format the robot delivers for `wanted`, if it can.
std::optional<Image::PixelFormat> deliverable(int wanted, bool colour_robot) {
  const auto native = colour_robot ? Image::PIXEL_FORMAT_RGB_U8 : Image::PIXEL_FORMAT_GREYSCALE_U8;
  if (wanted == Image::PIXEL_FORMAT_UNKNOWN) return native;
  if (wanted == Image::PIXEL_FORMAT_GREYSCALE_U8) return Image::PIXEL_FORMAT_GREYSCALE_U8;
  if (wanted == Image::PIXEL_FORMAT_RGB_U8 && colour_robot) return Image::PIXEL_FORMAT_RGB_U8;
  return std::nullopt;
}

int jpeg_quality(double percent) {
  if (!(percent > 0)) return kDefaultJpegQuality;  // unset (0) or NaN
  return static_cast<int>(std::lround(std::clamp(percent, 1.0, 100.0)));
}

}  // namespace

ImagePlan plan_image(const bosdyn::api::ImageRequest& request, bool colour_robot) {
  ImagePlan plan;
  plan.camera = find_camera(request.image_source_name(), plan.depth);
  if (!plan.camera) {
    plan.status = ImageResponse::STATUS_UNKNOWN_CAMERA;
    return plan;
  }
  if (request.resize_ratio() != 0 && request.resize_ratio() != 1) {  // NaN too
    plan.status = ImageResponse::STATUS_UNSUPPORTED_RESIZE_RATIO_REQUESTED;
    return plan;
  }
  if (plan.depth) {
    plan_depth(request, plan);
    return plan;
  }
  switch (request.image_format()) {
    case Image::FORMAT_UNKNOWN:
    case Image::FORMAT_JPEG:
      plan.encoding = Encoding::kJpeg;
      plan.quality = jpeg_quality(request.quality_percent());
      break;
    case Image::FORMAT_RAW:
      plan.encoding = Encoding::kRaw;
      break;
    default:
      plan.status = ImageResponse::STATUS_UNSUPPORTED_IMAGE_FORMAT_REQUESTED;
      return plan;
  }
  std::optional<Image::PixelFormat> format = deliverable(request.pixel_format(), colour_robot);
  for (int i = 0; !format && i < request.fallback_formats_size(); ++i) {
    format = deliverable(request.fallback_formats(i), colour_robot);
  }
  if (!format) {
    plan.status = ImageResponse::STATUS_UNSUPPORTED_PIXEL_FORMAT_REQUESTED;
    return plan;
  }
  plan.pixel_format = *format;
  return plan;
}

}  // namespace omniview::spot_mock
