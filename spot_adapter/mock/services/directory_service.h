// bosdyn.api.DirectoryService: which services the robot offers and at which authority.
#pragma once

#include "bosdyn/api/directory_service.grpc.pb.h"
#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

class DirectoryService final : public bosdyn::api::DirectoryService::Service {
 public:
  explicit DirectoryService(MockRobot& robot);
  grpc::Status GetServiceEntry(grpc::ServerContext* ctx, const bosdyn::api::GetServiceEntryRequest* request,
                               bosdyn::api::GetServiceEntryResponse* response) override;
  grpc::Status ListServiceEntries(grpc::ServerContext* ctx, const bosdyn::api::ListServiceEntriesRequest* request,
                                  bosdyn::api::ListServiceEntriesResponse* response) override;

 private:
  MockRobot& robot_;
  std::vector<bosdyn::api::ServiceEntry> entries_;
};

}  // namespace omniview::spot_mock
