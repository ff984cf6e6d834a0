#include "spot_adapter/source/image_set.h"

#include <google/protobuf/util/time_util.h>

#include "spot_adapter/client/spot_error.h"
#include "spot_adapter/convert/depth_from_response.h"
#include "spot_adapter/convert/image_from_response.h"

namespace omniview::spot {
namespace {

namespace api = bosdyn::api;
using google::protobuf::util::TimeUtil;

std::chrono::system_clock::time_point to_time_point(const google::protobuf::Timestamp& t) {
  return std::chrono::system_clock::time_point(
      std::chrono::duration_cast<std::chrono::system_clock::duration>(
          std::chrono::nanoseconds(TimeUtil::TimestampToNanoseconds(t))));
}

// Every 4th pixel each way: 19 200 points from a 640x480 depth image, ~100 000 for Spot's
// five cameras (GeometryOptions::max_points is 300 000); a view's pixel is finer only where
// the camera is nearer than the view's own pixels are wide.
constexpr int kDepthStep = 4;

}  // namespace

api::GetImageRequest image_request(const RobotSession& session, const SpotSettings& settings,
                                   const std::vector<CameraSlot>& slots, const std::vector<size_t>& wanted,
                                   const std::vector<size_t>& depth) {
  api::GetImageRequest request;
  *request.mutable_header() = session.request_header();
  for (size_t i : wanted) {
    auto* r = request.add_image_requests();
    r->set_image_source_name(slots[i].source);
    r->set_image_format(settings.jpeg ? api::Image::FORMAT_JPEG : api::Image::FORMAT_RAW);
    if (settings.jpeg) r->set_quality_percent(settings.jpeg_quality);
    r->set_pixel_format(slots[i].pixel_format);
    // A greyscale robot refuses RGB and a colour one may refuse greyscale: name the other.
    if (slots[i].pixel_format != api::Image::PIXEL_FORMAT_UNKNOWN) {
      r->add_fallback_formats(slots[i].pixel_format == api::Image::PIXEL_FORMAT_RGB_U8
                                  ? api::Image::PIXEL_FORMAT_GREYSCALE_U8
                                  : api::Image::PIXEL_FORMAT_RGB_U8);
    }
  }
  for (size_t i : depth) {
    auto* r = request.add_image_requests();
    r->set_image_source_name(slots[i].depth_source);
    r->set_image_format(api::Image::FORMAT_RAW);
    r->set_pixel_format(api::Image::PIXEL_FORMAT_DEPTH_U16);
  }
  return request;
}

ImageSet images_from_response(const api::GetImageRequest& request, const api::GetImageResponse& response,
                              std::vector<CameraSlot>& slots, const std::vector<size_t>& wanted,
                              const std::vector<size_t>& depth) {
  check_header(response.header(), "GetImage");
  if (response.image_responses_size() != request.image_requests_size() ||
      static_cast<size_t>(request.image_requests_size()) != wanted.size() + depth.size()) {
    throw SpotError(SpotError::Kind::kProtocol, "GetImage answered " + std::to_string(response.image_responses_size()) +
                                                    " images for " + std::to_string(request.image_requests_size()) +
                                                    " requested");
  }

  ImageSet set;
  set.images.resize(slots.size());
  set.encoded.resize(slots.size());
  for (size_t k = 0; k < wanted.size(); ++k) {
    CameraSlot& slot = slots[wanted[k]];
    const api::ImageResponse& r = response.image_responses(static_cast<int>(k));
    if (r.status() == api::ImageResponse::STATUS_UNSUPPORTED_PIXEL_FORMAT_REQUESTED) {
      slot.pixel_format = api::Image::PIXEL_FORMAT_UNKNOWN;  // take what the camera has, next time
    }
    try {
      // Responses come in request order; a robot that mixes them up names another source.
      if (!r.source().name().empty() && r.source().name() != slot.source) {
        throw SpotError(SpotError::Kind::kProtocol, "camera '" + slot.camera.name + "': response is for source '" +
                                                        r.source().name() + "'");
      }
      DecodedImage d = decode_image_response(r, slot.camera.name, slot.camera.width, slot.camera.height);
      const auto& shot = r.shot();
      for (auto& e : frame_edges(shot.transforms_snapshot(), "image '" + slot.source + "'")) {
        set.edges.push_back(std::move(e));
      }
      if (set.good == 0 && shot.has_acquisition_time()) {
        set.capture_time = to_time_point(shot.acquisition_time());
        set.robot_time = true;
      }
      set.images[wanted[k]] = std::move(d.image);
      set.encoded[wanted[k]] = std::move(d.encoded);
      ++set.good;
    } catch (const SpotError& e) {
      set.problems.push_back(e.what());
    }
  }
  for (size_t k = 0; k < depth.size(); ++k) {
    const CameraSlot& slot = slots[depth[k]];
    const api::ImageResponse& r = response.image_responses(static_cast<int>(wanted.size() + k));
    try {
      if (!r.source().name().empty() && r.source().name() != slot.depth_source) {
        throw SpotError(SpotError::Kind::kProtocol, "depth of camera '" + slot.camera.name +
                                                        "': response is for source '" + r.source().name() + "'");
      }
      set.depth.push_back({depth[k], points_from_depth_response(r, slot.camera, kDepthStep)});
    } catch (const SpotError& e) {
      set.depth_problems.push_back(e.what());
    }
  }
  if (set.good > 0 && set.capture_time == std::chrono::system_clock::time_point{}) {
    set.capture_time = std::chrono::system_clock::now();  // a robot that sends no time
  }
  return set;
}

}  // namespace omniview::spot
