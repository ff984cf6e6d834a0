#include "spot_adapter/client/robot_clock.h"

#include <google/protobuf/util/time_util.h>

#include "bosdyn/api/time_sync_service.grpc.pb.h"
#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {

namespace api = bosdyn::api;
using google::protobuf::util::TimeUtil;

namespace {
// This machine's clock to the nanosecond (protobuf's TimeUtil::GetCurrentTime() may give
// whole seconds, which would put the skew off by up to one).
google::protobuf::Timestamp now() {
  return TimeUtil::NanosecondsToTimestamp(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}
}  // namespace

bool RobotClock::exchange(RobotSession& session) {
  api::TimeSyncUpdateRequest request;
  if (previous_.has_client_rx()) *request.mutable_previous_round_trip() = previous_;
  request.set_clock_identifier(clock_id_);
  const auto sent = now();
  const api::TimeSyncUpdateResponse response =
      session.call("time-sync", &api::TimeSyncService::Stub::TimeSyncUpdate, request, "TimeSyncUpdate");
  const auto received = now();
  clock_id_ = response.clock_identifier();
  // This round trip, for the robot to measure with the next exchange.
  previous_.Clear();
  *previous_.mutable_client_tx() = sent;
  *previous_.mutable_server_rx() = response.header().request_received_timestamp();
  *previous_.mutable_server_tx() = response.header().response_timestamp();
  *previous_.mutable_client_rx() = received;
  const auto& state = response.state();
  if (state.status() != api::TimeSyncState::STATUS_OK || !state.best_estimate().has_clock_skew()) return false;
  skew_ = std::chrono::nanoseconds(TimeUtil::DurationToNanoseconds(state.best_estimate().clock_skew()));
  round_trip_ = std::chrono::nanoseconds(TimeUtil::DurationToNanoseconds(state.best_estimate().round_trip_time()));
  synced_ = true;
  return true;
}

void RobotClock::sync(RobotSession& session, int max_exchanges) {
  for (int i = 0; i < max_exchanges; ++i) {
    if (exchange(session)) return;
  }
}

void RobotClock::update(RobotSession& session) { exchange(session); }

void RobotClock::reset() {
  previous_.Clear();
  clock_id_.clear();
  synced_ = false;
  skew_ = round_trip_ = std::chrono::nanoseconds(0);
}

}  // namespace omniview::spot
