// What every bosdyn.api call passes first, as on the robot's proxy: the "away" fault (the
// robot is unreachable), the injected latency, and the bearer token where one is required.
#pragma once

#include <grpcpp/server_context.h>
#include <grpcpp/support/status.h>

#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

enum class Token { kRequired, kNotRequired };

// OK to go on, or the status to answer the call with (UNAVAILABLE, UNAUTHENTICATED).
grpc::Status admit_call(MockRobot& robot, const grpc::ServerContext& ctx, Token token);

}  // namespace omniview::spot_mock
