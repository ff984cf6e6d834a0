// What every bosdyn.api call passes first, as on the robot's proxy: the "away" fault (the
// robot is unreachable), the injected latency, and the bearer token where one is required.
#pragma once

#include <grpcpp/server_context.h>
#include <grpcpp/support/status.h>

#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

enum class Token { kRequired, kNotRequired };

// OK to go on, or the status to answer the call with (UNAVAILABLE, UNAUTHENTICATED).
// Waits the first half of the injected latency: the request's way to the robot.
grpc::Status admit_call(MockRobot& robot, const grpc::ServerContext& ctx, Token token);

// The injected latency's second half, waited when it goes out of scope: the answer's way
// back, after the robot stamped its times (so ages and time sync see a real link's delays).
class ReturnTrip {
 public:
  explicit ReturnTrip(MockRobot& robot);
  ~ReturnTrip();
  ReturnTrip(const ReturnTrip&) = delete;
  ReturnTrip& operator=(const ReturnTrip&) = delete;

 private:
  int delay_ms_;
};

}  // namespace omniview::spot_mock
