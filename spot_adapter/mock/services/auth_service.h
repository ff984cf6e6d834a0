// bosdyn.api.AuthService: username/password login and token refresh (no token needed).
#pragma once

#include "bosdyn/api/auth_service.grpc.pb.h"
#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

class AuthService final : public bosdyn::api::AuthService::Service {
 public:
  explicit AuthService(MockRobot& robot) : robot_(robot) {}
  grpc::Status GetAuthToken(grpc::ServerContext* ctx, const bosdyn::api::GetAuthTokenRequest* request,
                            bosdyn::api::GetAuthTokenResponse* response) override;

 private:
  MockRobot& robot_;
};

}  // namespace omniview::spot_mock
