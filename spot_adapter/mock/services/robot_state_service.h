// bosdyn.api.RobotStateService: the leg joints' angles and the frame tree.
#pragma once

#include "bosdyn/api/robot_state_service.grpc.pb.h"
#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

class RobotStateService final : public bosdyn::api::RobotStateService::Service {
 public:
  explicit RobotStateService(MockRobot& robot) : robot_(robot) {}
  grpc::Status GetRobotState(grpc::ServerContext* ctx, const bosdyn::api::RobotStateRequest* request,
                             bosdyn::api::RobotStateResponse* response) override;

 private:
  MockRobot& robot_;
};

}  // namespace omniview::spot_mock
