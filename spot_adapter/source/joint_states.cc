#include "spot_adapter/source/joint_states.h"

#include <cmath>

#include "bosdyn/api/robot_state_service.grpc.pb.h"
#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {

std::shared_ptr<const JointMap> get_joint_states(RobotSession& session) {
  bosdyn::api::RobotStateRequest request;
  *request.mutable_header() = session.request_header();
  bosdyn::api::RobotStateResponse response;
  grpc::ClientContext context;
  session.prepare(context, true);
  const auto stub = bosdyn::api::RobotStateService::NewStub(session.service_channel("robot-state"));
  {
    RobotSession::CallScope scope(session, context);
    check_status(stub->GetRobotState(&context, request, &response), "GetRobotState");
  }
  check_header(response.header(), "GetRobotState");
  auto joints = std::make_shared<JointMap>();
  for (const auto& j : response.robot_state().kinematic_state().joint_states()) {
    // A joint the robot cannot measure right now comes without a position.
    if (!j.name().empty() && j.has_position() && std::isfinite(j.position().value())) {
      (*joints)[j.name()] = j.position().value();
    }
  }
  return joints;
}

}  // namespace omniview::spot
