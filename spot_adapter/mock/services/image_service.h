// bosdyn.api.ImageService: the five body cameras, with the faults the control service sets.
#pragma once

#include <vector>

#include "bosdyn/api/image_service.grpc.pb.h"
#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

class ImageService final : public bosdyn::api::ImageService::Service {
 public:
  explicit ImageService(MockRobot& robot);
  grpc::Status ListImageSources(grpc::ServerContext* ctx, const bosdyn::api::ListImageSourcesRequest* request,
                                bosdyn::api::ListImageSourcesResponse* response) override;
  grpc::Status GetImage(grpc::ServerContext* ctx, const bosdyn::api::GetImageRequest* request,
                        bosdyn::api::GetImageResponse* response) override;

 private:
  void answer(const bosdyn::api::ImageRequest& request, const google::protobuf::Timestamp& acquired,
              const FaultSettings& faults, bosdyn::api::ImageResponse* response);

  MockRobot& robot_;
  std::vector<bosdyn::api::ImageSource> sources_;        // the five cameras, in mock_cameras() order
  std::vector<bosdyn::api::ImageSource> depth_sources_;  // and their depth, in the same order
};

}  // namespace omniview::spot_mock
