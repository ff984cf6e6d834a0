// Directory and robot id: what a Spot client reads first to find the other services.
#include <map>

#include "bosdyn/api/directory_service.grpc.pb.h"
#include "bosdyn/api/robot_id_service.grpc.pb.h"
#include "tests/spot_mock/mock_fixture.h"

namespace omniview::testing {
namespace {

using bosdyn::api::GetServiceEntryResponse;

class SpotMockDiscovery : public SharedMockTest {
 protected:
  std::unique_ptr<bosdyn::api::DirectoryService::Stub> directory() {
    return bosdyn::api::DirectoryService::NewStub(mock().channel("api.spot.robot"));
  }
};

TEST_F(SpotMockDiscovery, DirectoryListsTheServicesWithTypeAndAuthority) {
  bosdyn::api::ListServiceEntriesRequest request;
  request.mutable_header()->set_client_name("discovery-test");
  bosdyn::api::ListServiceEntriesResponse response;
  ASSERT_TRUE(directory()->ListServiceEntries(spot_context(mock().login()).get(), request, &response).ok());
  EXPECT_EQ(response.header().error().code(), bosdyn::api::CommonError::CODE_OK);
  EXPECT_EQ(response.header().request_header().client_name(), "discovery-test");

  std::map<std::string, std::pair<std::string, std::string>> entries;  // name -> (type, authority)
  for (const auto& e : response.service_entries()) entries[e.name()] = {e.type(), e.authority()};
  const std::map<std::string, std::pair<std::string, std::string>> expected = {
      {"auth", {"bosdyn.api.AuthService", "auth.spot.robot"}},
      {"directory", {"bosdyn.api.DirectoryService", "api.spot.robot"}},
      {"robot-id", {"bosdyn.api.RobotIdService", "id.spot.robot"}},
      {"image", {"bosdyn.api.ImageService", "api.spot.robot"}},
      {"point-cloud", {"bosdyn.api.PointCloudService", "api.spot.robot"}},
      {"robot-state", {"bosdyn.api.RobotStateService", "api.spot.robot"}},
      {"time-sync", {"bosdyn.api.TimeSyncService", "api.spot.robot"}},
  };
  EXPECT_EQ(entries, expected);
}

TEST_F(SpotMockDiscovery, GetServiceEntryByNameOrNonexistent) {
  const std::string token = mock().login();
  bosdyn::api::GetServiceEntryRequest request;
  request.set_service_name("image");
  GetServiceEntryResponse response;
  ASSERT_TRUE(directory()->GetServiceEntry(spot_context(token).get(), request, &response).ok());
  EXPECT_EQ(response.status(), GetServiceEntryResponse::STATUS_OK);
  EXPECT_EQ(response.service_entry().type(), "bosdyn.api.ImageService");
  EXPECT_TRUE(response.service_entry().user_token_required());

  request.set_service_name("arm-surface-contact");
  ASSERT_TRUE(directory()->GetServiceEntry(spot_context(token).get(), request, &response).ok());
  EXPECT_EQ(response.status(), GetServiceEntryResponse::STATUS_NONEXISTENT_SERVICE);
}

TEST_F(SpotMockDiscovery, RobotIdNeedsNoToken) {
  bosdyn::api::RobotIdResponse response;
  ASSERT_TRUE(bosdyn::api::RobotIdService::NewStub(mock().channel("id.spot.robot"))
                  ->GetRobotId(spot_context().get(), {}, &response)
                  .ok());
  EXPECT_EQ(response.header().error().code(), bosdyn::api::CommonError::CODE_OK);
  EXPECT_EQ(response.robot_id().species(), "spot");
  EXPECT_EQ(response.robot_id().nickname(), "spot-mock");
  EXPECT_FALSE(response.robot_id().serial_number().empty());
  EXPECT_FALSE(response.robot_id().version().empty());
}

}  // namespace
}  // namespace omniview::testing
