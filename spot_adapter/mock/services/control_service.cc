#include "spot_adapter/mock/services/control_service.h"

#include <cmath>
#include <stdexcept>

namespace omniview::spot_mock {
namespace {

namespace v1 = omniview::spotmock::v1;

constexpr uint32_t kMaxLatencyMs = 60'000;

v1::Faults to_proto(const FaultSettings& s) {
  v1::Faults f;
  f.set_latency_ms(static_cast<uint32_t>(s.latency_ms));
  f.set_fail_probability(s.fail_probability);
  f.set_image_error_probability(s.image_error_probability);
  f.set_corrupt_probability(s.corrupt_probability);
  f.set_wrong_size_probability(s.wrong_size_probability);
  f.set_away(s.away);
  return f;
}

grpc::Status check(const v1::Faults& f) {
  const auto bad_probability = [](bool has, double p) { return has && !(p >= 0 && p <= 1); };
  if (bad_probability(f.has_fail_probability(), f.fail_probability()) ||
      bad_probability(f.has_image_error_probability(), f.image_error_probability()) ||
      bad_probability(f.has_corrupt_probability(), f.corrupt_probability()) ||
      bad_probability(f.has_wrong_size_probability(), f.wrong_size_probability())) {
    return {grpc::StatusCode::INVALID_ARGUMENT, "probabilities must lie in [0, 1]"};
  }
  if (f.has_latency_ms() && f.latency_ms() > kMaxLatencyMs) {
    return {grpc::StatusCode::INVALID_ARGUMENT, "latency_ms must be at most 60000"};
  }
  return grpc::Status::OK;
}

}  // namespace

grpc::Status ControlService::SetFaults(grpc::ServerContext*, const v1::SetFaultsRequest* request,
                                       v1::SetFaultsResponse* response) {
  const v1::Faults& f = request->faults();
  if (auto status = check(f); !status.ok()) return status;
  const FaultSettings now = robot_.faults.update([&](FaultSettings& s) {
    if (f.has_latency_ms()) s.latency_ms = static_cast<int>(f.latency_ms());
    if (f.has_fail_probability()) s.fail_probability = f.fail_probability();
    if (f.has_image_error_probability()) s.image_error_probability = f.image_error_probability();
    if (f.has_corrupt_probability()) s.corrupt_probability = f.corrupt_probability();
    if (f.has_wrong_size_probability()) s.wrong_size_probability = f.wrong_size_probability();
    if (f.has_away()) s.away = f.away();
  });
  *response->mutable_faults() = to_proto(now);
  return grpc::Status::OK;
}

grpc::Status ControlService::GetFaults(grpc::ServerContext*, const v1::GetFaultsRequest*,
                                       v1::GetFaultsResponse* response) {
  *response->mutable_faults() = to_proto(robot_.faults.get());
  return grpc::Status::OK;
}

grpc::Status ControlService::ExpireTokens(grpc::ServerContext*, const v1::ExpireTokensRequest*,
                                          v1::ExpireTokensResponse* response) {
  response->set_expired(static_cast<uint32_t>(robot_.tokens.expire_all()));
  return grpc::Status::OK;
}

grpc::Status ControlService::SetJointAngles(grpc::ServerContext*, const v1::SetJointAnglesRequest* request,
                                            v1::SetJointAnglesResponse* response) {
  try {
    const auto angles = robot_.joints.set({request->positions().begin(), request->positions().end()});
    response->mutable_positions()->insert(angles.begin(), angles.end());
    return grpc::Status::OK;
  } catch (const std::invalid_argument& e) {
    return {grpc::StatusCode::INVALID_ARGUMENT, e.what()};
  }
}

grpc::Status ControlService::GetCounters(grpc::ServerContext*, const v1::GetCountersRequest* request,
                                         v1::GetCountersResponse* response) {
  const CounterValues c = robot_.counters.read(request->reset());
  auto* out = response->mutable_counters();
  out->set_get_image_calls(c.get_image_calls);
  out->mutable_image_requests_by_source()->insert(c.image_requests_by_source.begin(), c.image_requests_by_source.end());
  out->set_logins_ok(c.logins_ok);
  out->set_logins_failed(c.logins_failed);
  out->set_token_refreshes(c.token_refreshes);
  out->set_auth_rejections(c.auth_rejections);
  out->set_list_image_sources_calls(c.list_image_sources_calls);
  out->set_get_point_cloud_calls(c.get_point_cloud_calls);
  out->set_get_robot_state_calls(c.get_robot_state_calls);
  return grpc::Status::OK;
}

}  // namespace omniview::spot_mock
