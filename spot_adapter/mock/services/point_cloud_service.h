// bosdyn.api.PointCloudService: one lidar (like Spot's EAP Velodyne) scanning the scene.
#pragma once

#include "bosdyn/api/point_cloud_service.grpc.pb.h"
#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

class PointCloudService final : public bosdyn::api::PointCloudService::Service {
 public:
  explicit PointCloudService(MockRobot& robot) : robot_(robot) {}
  grpc::Status ListPointCloudSources(grpc::ServerContext* ctx, const bosdyn::api::ListPointCloudSourcesRequest* request,
                                     bosdyn::api::ListPointCloudSourcesResponse* response) override;
  grpc::Status GetPointCloud(grpc::ServerContext* ctx, const bosdyn::api::GetPointCloudRequest* request,
                             bosdyn::api::GetPointCloudResponse* response) override;

 private:
  bosdyn::api::PointCloudSource describe_source() const;
  MockRobot& robot_;
};

}  // namespace omniview::spot_mock
