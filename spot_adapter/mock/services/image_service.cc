#include "spot_adapter/mock/services/image_service.h"

#include "spot_adapter/mock/services/call_gate.h"
#include "spot_adapter/mock/services/image_request_plan.h"
#include "spot_adapter/mock/services/image_sources.h"
#include "spot_adapter/mock/wire/spot_messages.h"

namespace omniview::spot_mock {
namespace {

using bosdyn::api::Image;
using bosdyn::api::ImageResponse;

constexpr int kMaxImageRequests = 64;

// Half the time cut short (decoders may still show the top of the picture), half the time
// overwritten from the start (nothing decodes).
void corrupt(std::string& bytes) {
  if (chance(0.5)) {
    bytes.resize(bytes.size() / 3);
  } else {
    for (size_t i = 0; i < std::min<size_t>(bytes.size(), 64); ++i) bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
  }
}

}  // namespace

ImageService::ImageService(MockRobot& robot) : robot_(robot) {
  for (size_t i = 0; i < mock_cameras().size(); ++i) {
    sources_.push_back(describe_source(mock_cameras()[i], robot.rig.cameras().at(i), robot.cameras.colour()));
    depth_sources_.push_back(describe_depth_source(mock_cameras()[i], robot.rig.cameras().at(i)));
  }
}

grpc::Status ImageService::ListImageSources(grpc::ServerContext* ctx, const bosdyn::api::ListImageSourcesRequest* request,
                                            bosdyn::api::ListImageSourcesResponse* response) {
  if (auto status = admit_call(robot_, *ctx, Token::kRequired); !status.ok()) return status;
  const ReturnTrip return_trip(robot_);  // the answer travels back after it is stamped
  const auto received = now_timestamp();
  robot_.counters.increment(&CounterValues::list_image_sources_calls);
  fill_response_header(request->header(), received, response->mutable_header());
  for (const auto& s : sources_) *response->add_image_sources() = s;
  for (const auto& s : depth_sources_) *response->add_image_sources() = s;
  *response->mutable_transforms_snapshot() = mock_frame_tree_snapshot();
  return grpc::Status::OK;
}

grpc::Status ImageService::GetImage(grpc::ServerContext* ctx, const bosdyn::api::GetImageRequest* request,
                                    bosdyn::api::GetImageResponse* response) {
  if (auto status = admit_call(robot_, *ctx, Token::kRequired); !status.ok()) return status;
  const ReturnTrip return_trip(robot_);  // the answer travels back after it is stamped
  const auto received = now_timestamp();
  robot_.counters.increment(&CounterValues::get_image_calls);
  for (const auto& r : request->image_requests()) robot_.counters.count_image_request(r.image_source_name());
  fill_response_header(request->header(), received, response->mutable_header());
  if (request->image_requests_size() > kMaxImageRequests) {
    // A bound on the answer's size: each image is up to 1 MB.
    set_header_error(response->mutable_header(), bosdyn::api::CommonError::CODE_INVALID_REQUEST,
                     "spot-mock answers at most " + std::to_string(kMaxImageRequests) + " image requests a call");
    return grpc::Status::OK;
  }

  const FaultSettings faults = robot_.faults.get();
  if (chance(faults.fail_probability)) {
    // Both ways a robot's image service is seen to fail: the proxy, or the service itself.
    if (chance(0.5)) return {grpc::StatusCode::UNAVAILABLE, "spot-mock: image service failed (fault injected)"};
    set_header_error(response->mutable_header(), bosdyn::api::CommonError::CODE_INTERNAL_SERVER_ERROR,
                     "spot-mock: image service failed (fault injected)");
    return grpc::Status::OK;
  }
  // One acquisition time for all: the body cameras are hardware-synchronised.
  const auto acquired = now_timestamp();
  for (const auto& r : request->image_requests()) answer(r, acquired, faults, response->add_image_responses());
  return grpc::Status::OK;
}

void ImageService::answer(const bosdyn::api::ImageRequest& request, const google::protobuf::Timestamp& acquired,
                          const FaultSettings& faults, ImageResponse* response) {
  const ImagePlan plan = plan_image(request, robot_.cameras.colour());
  response->set_status(plan.status);
  if (plan.camera) *response->mutable_source() = plan.depth ? depth_sources_[*plan.camera] : sources_[*plan.camera];
  if (plan.status != ImageResponse::STATUS_OK) return;
  if (chance(faults.image_error_probability)) {
    response->set_status(ImageResponse::STATUS_IMAGE_DATA_ERROR);
    return;
  }
  const size_t cam = *plan.camera;
  auto* shot = response->mutable_shot();
  *shot->mutable_acquisition_time() = acquired;
  *shot->mutable_transforms_snapshot() = mock_frame_tree_snapshot();
  shot->set_frame_name_image_sensor(mock_cameras()[cam].sensor_frame);
  shot->mutable_capture_params()->mutable_exposure_duration()->set_nanos(8'000'000);
  shot->mutable_capture_params()->set_gain(1.0);

  Image* image = shot->mutable_image();
  const bool grey = plan.pixel_format == Image::PIXEL_FORMAT_GREYSCALE_U8;
  std::string bytes = plan.depth ? robot_.depths.raw(cam) : robot_.cameras.encoded(cam, plan.encoding, grey, plan.quality);
  if (chance(faults.corrupt_probability)) corrupt(bytes);
  image->set_data(std::move(bytes));
  image->set_format(plan.encoding == Encoding::kJpeg ? Image::FORMAT_JPEG : Image::FORMAT_RAW);
  image->set_pixel_format(plan.pixel_format);
  const cv::Mat& picture = robot_.cameras.image(cam);
  const bool wrong_size = chance(faults.wrong_size_probability);
  image->set_cols(wrong_size ? picture.cols / 2 : picture.cols);
  image->set_rows(wrong_size ? picture.rows / 2 : picture.rows);
}

}  // namespace omniview::spot_mock
