#include "spot_adapter/mock/services/robot_id_service.h"

#include "spot_adapter/mock/services/call_gate.h"
#include "spot_adapter/mock/wire/spot_messages.h"

namespace omniview::spot_mock {

grpc::Status RobotIdService::GetRobotId(grpc::ServerContext* ctx, const bosdyn::api::RobotIdRequest* request,
                                        bosdyn::api::RobotIdResponse* response) {
  if (auto status = admit_call(robot_, *ctx, Token::kNotRequired); !status.ok()) return status;
  const ReturnTrip return_trip(robot_);  // the answer travels back after it is stamped
  const auto received = now_timestamp();
  fill_response_header(request->header(), received, response->mutable_header());
  auto* id = response->mutable_robot_id();
  id->set_serial_number(kMockSerial);
  id->set_species("spot");
  id->set_version("mock-1.0");
  id->set_nickname(kMockNickname);
  id->set_computer_serial_number("spot-mock-computer-0001");
  return grpc::Status::OK;
}

}  // namespace omniview::spot_mock
