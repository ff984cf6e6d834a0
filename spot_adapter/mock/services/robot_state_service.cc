#include "spot_adapter/mock/services/robot_state_service.h"

#include "spot_adapter/mock/services/call_gate.h"
#include "spot_adapter/mock/wire/spot_messages.h"

namespace omniview::spot_mock {

grpc::Status RobotStateService::GetRobotState(grpc::ServerContext* ctx, const bosdyn::api::RobotStateRequest* request,
                                              bosdyn::api::RobotStateResponse* response) {
  if (auto status = admit_call(robot_, *ctx, Token::kRequired); !status.ok()) return status;
  const ReturnTrip return_trip(robot_);  // the answer travels back after it is stamped
  const auto received = now_timestamp();
  robot_.counters.increment(&CounterValues::get_robot_state_calls);
  fill_response_header(request->header(), received, response->mutable_header());
  auto* kinematics = response->mutable_robot_state()->mutable_kinematic_state();
  const auto angles = robot_.joints.get();
  for (const auto& name : joint_names()) {  // in Spot's order, not the map's
    auto* joint = kinematics->add_joint_states();
    joint->set_name(name);
    joint->mutable_position()->set_value(angles.at(name));
  }
  *kinematics->mutable_acquisition_timestamp() = now_timestamp();
  *kinematics->mutable_transforms_snapshot() = mock_frame_tree_snapshot();
  return grpc::Status::OK;
}

}  // namespace omniview::spot_mock
