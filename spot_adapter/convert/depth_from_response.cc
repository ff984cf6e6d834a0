#include "spot_adapter/convert/depth_from_response.h"

#include <cmath>

#include "core/depth/depth_image_points.h"
#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {
namespace {

namespace api = bosdyn::api;

[[noreturn]] void fail_depth(const std::string& camera, const std::string& message) {
  throw SpotError(SpotError::Kind::kProtocol, "depth of camera '" + camera + "': " + message);
}

}  // namespace

std::string depth_source_for(const std::string& image_source) {
  for (const std::string suffix : {"_fisheye_image", "_image"}) {
    if (image_source.size() > suffix.size() &&
        image_source.compare(image_source.size() - suffix.size(), suffix.size(), suffix) == 0) {
      return image_source.substr(0, image_source.size() - suffix.size()) + "_depth_in_visual_frame";
    }
  }
  return image_source + "_depth_in_visual_frame";
}

std::vector<Eigen::Vector3f> points_from_depth_response(const api::ImageResponse& response, const Camera& camera,
                                                        int step, double max_range_m) {
  const std::string& name = camera.name;
  if (response.status() != api::ImageResponse::STATUS_OK) {
    fail_depth(name, "the robot answered " + api::ImageResponse::Status_Name(response.status()));
  }
  const api::Image& img = response.shot().image();
  if (img.format() != api::Image::FORMAT_RAW || img.pixel_format() != api::Image::PIXEL_FORMAT_DEPTH_U16) {
    fail_depth(name, "expected RAW DEPTH_U16, got " + api::Image::Format_Name(img.format()) + " " +
                         api::Image::PixelFormat_Name(img.pixel_format()));
  }
  if (img.cols() != camera.width || img.rows() != camera.height) {
    fail_depth(name, "image is " + std::to_string(img.cols()) + "x" + std::to_string(img.rows()) +
                         ", the camera is calibrated for " + std::to_string(camera.width) + "x" +
                         std::to_string(camera.height));
  }
  const auto pixels = static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height);
  const std::string& data = img.data();
  if (data.size() != 2 * pixels) {
    fail_depth(name, "carries " + std::to_string(data.size()) + " bytes for " + std::to_string(pixels) +
                         " 16-bit pixels");
  }
  const double scale = response.source().depth_scale();
  if (!(scale > 0) || !std::isfinite(scale)) {
    fail_depth(name, "its source gives no usable depth_scale (" + std::to_string(scale) + ")");
  }
  return depth_image_points(DepthImage{{reinterpret_cast<const uint8_t*>(data.data()), data.size()}, scale}, camera,
                            step, max_range_m);
}

}  // namespace omniview::spot
