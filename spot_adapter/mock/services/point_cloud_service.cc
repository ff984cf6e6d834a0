#include "spot_adapter/mock/services/point_cloud_service.h"

#include "spot_adapter/mock/services/call_gate.h"
#include "spot_adapter/mock/wire/spot_messages.h"

namespace omniview::spot_mock {
namespace {

using bosdyn::api::PointCloud;
using bosdyn::api::PointCloudResponse;

constexpr size_t kBytesPerPoint = 12;  // XYZ_32F
constexpr int kMaxCloudRequests = 16;

// Every n-th point, as downsample_rate asks (<= 1: all of them).
std::string downsample(const std::string& xyz, int rate, int* num_points) {
  const size_t points = xyz.size() / kBytesPerPoint;
  if (rate <= 1) {
    *num_points = static_cast<int>(points);
    return xyz;
  }
  std::string out;
  for (size_t i = 0; i < points; i += static_cast<size_t>(rate)) out.append(xyz, i * kBytesPerPoint, kBytesPerPoint);
  *num_points = static_cast<int>(out.size() / kBytesPerPoint);
  return out;
}

}  // namespace

bosdyn::api::PointCloudSource PointCloudService::describe_source() const {
  bosdyn::api::PointCloudSource s;
  s.set_name(kLidarSource);
  s.set_frame_name_sensor(kLidarFrame);
  s.add_supported_cloud_types(bosdyn::api::PointCloudRequest::CLOUD_TYPE_POINTS);
  return s;
}

grpc::Status PointCloudService::ListPointCloudSources(grpc::ServerContext* ctx,
                                                      const bosdyn::api::ListPointCloudSourcesRequest* request,
                                                      bosdyn::api::ListPointCloudSourcesResponse* response) {
  if (auto status = admit_call(robot_, *ctx, Token::kRequired); !status.ok()) return status;
  const ReturnTrip return_trip(robot_);  // the answer travels back after it is stamped
  const auto received = now_timestamp();
  fill_response_header(request->header(), received, response->mutable_header());
  *response->add_point_cloud_sources() = describe_source();
  return grpc::Status::OK;
}

grpc::Status PointCloudService::GetPointCloud(grpc::ServerContext* ctx, const bosdyn::api::GetPointCloudRequest* request,
                                              bosdyn::api::GetPointCloudResponse* response) {
  if (auto status = admit_call(robot_, *ctx, Token::kRequired); !status.ok()) return status;
  const ReturnTrip return_trip(robot_);  // the answer travels back after it is stamped
  const auto received = now_timestamp();
  robot_.counters.increment(&CounterValues::get_point_cloud_calls);
  fill_response_header(request->header(), received, response->mutable_header());
  if (request->point_cloud_requests_size() > kMaxCloudRequests) {
    // A bound on the answer's size: each cloud is about 170 kB.
    set_header_error(response->mutable_header(), bosdyn::api::CommonError::CODE_INVALID_REQUEST,
                     "spot-mock answers at most " + std::to_string(kMaxCloudRequests) + " cloud requests a call");
    return grpc::Status::OK;
  }
  const auto acquired = now_timestamp();
  for (const auto& r : request->point_cloud_requests()) {
    PointCloudResponse* answer = response->add_point_cloud_responses();
    if (r.point_cloud_source_name() != kLidarSource) {
      answer->set_status(PointCloudResponse::STATUS_UNKNOWN_SOURCE);
      continue;
    }
    answer->set_status(PointCloudResponse::STATUS_OK);
    PointCloud* cloud = answer->mutable_point_cloud();
    *cloud->mutable_source() = describe_source();
    *cloud->mutable_source()->mutable_acquisition_time() = acquired;
    *cloud->mutable_source()->mutable_transforms_snapshot() = mock_frame_tree_snapshot();
    cloud->set_encoding(PointCloud::ENCODING_XYZ_32F);
    int num_points = 0;
    cloud->set_data(downsample(robot_.lidar.xyz_32f, r.downsample_rate(), &num_points));
    cloud->set_num_points(num_points);
    cloud->mutable_encoding_parameters()->set_bytes_per_point(static_cast<int>(kBytesPerPoint));
  }
  return grpc::Status::OK;
}

}  // namespace omniview::spot_mock
