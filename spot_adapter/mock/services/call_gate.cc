#include "spot_adapter/mock/services/call_gate.h"

#include <strings.h>

#include <string_view>
#include <thread>

namespace omniview::spot_mock {
namespace {

// The token in the call's `authorization: Bearer <token>` metadata; empty if absent or of
// another shape.
std::string bearer_token(const grpc::ServerContext& ctx) {
  const auto [begin, end] = ctx.client_metadata().equal_range("authorization");
  if (begin == end || std::next(begin) != end) return {};  // none, or ambiguous
  const std::string_view value(begin->second.data(), begin->second.size());
  constexpr std::string_view kScheme = "bearer ";
  if (value.size() <= kScheme.size() || strncasecmp(value.data(), kScheme.data(), kScheme.size()) != 0) return {};
  return std::string(value.substr(kScheme.size()));
}

}  // namespace

grpc::Status admit_call(MockRobot& robot, const grpc::ServerContext& ctx, Token token) {
  const FaultSettings faults = robot.faults.get();
  if (faults.away) return {grpc::StatusCode::UNAVAILABLE, "spot-mock: robot unreachable (fault injected: away)"};
  if (faults.latency_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(faults.latency_ms / 2));
  if (token == Token::kNotRequired) return grpc::Status::OK;

  const std::string presented = bearer_token(ctx);
  if (presented.empty()) {
    robot.counters.increment(&CounterValues::auth_rejections);
    return {grpc::StatusCode::UNAUTHENTICATED,
            "this service needs metadata `authorization: Bearer <token>`; get a token from "
            "AuthService.GetAuthToken on auth.spot.robot"};
  }
  if (!robot.tokens.valid(presented)) {
    robot.counters.increment(&CounterValues::auth_rejections);
    return {grpc::StatusCode::UNAUTHENTICATED,
            "the bearer token is not valid (expired, revoked or never issued): log in again"};
  }
  return grpc::Status::OK;
}

ReturnTrip::ReturnTrip(MockRobot& robot) {
  const int latency = robot.faults.get().latency_ms;
  delay_ms_ = latency - latency / 2;
}

ReturnTrip::~ReturnTrip() {
  if (delay_ms_ > 0) std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms_));
}

}  // namespace omniview::spot_mock
