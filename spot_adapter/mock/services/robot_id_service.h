// bosdyn.api.RobotIdService: who the robot is (no token needed).
#pragma once

#include "bosdyn/api/robot_id_service.grpc.pb.h"
#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

inline constexpr const char* kMockSerial = "spot-mock-0001";
inline constexpr const char* kMockNickname = "spot-mock";

class RobotIdService final : public bosdyn::api::RobotIdService::Service {
 public:
  explicit RobotIdService(MockRobot& robot) : robot_(robot) {}
  grpc::Status GetRobotId(grpc::ServerContext* ctx, const bosdyn::api::RobotIdRequest* request,
                          bosdyn::api::RobotIdResponse* response) override;

 private:
  MockRobot& robot_;
};

}  // namespace omniview::spot_mock
