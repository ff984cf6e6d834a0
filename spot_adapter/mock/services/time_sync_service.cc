#include "spot_adapter/mock/services/time_sync_service.h"

#include <google/protobuf/util/time_util.h>

#include "spot_adapter/mock/services/call_gate.h"
#include "spot_adapter/mock/wire/spot_messages.h"

namespace omniview::spot_mock {
namespace {

using google::protobuf::util::TimeUtil;
namespace api = bosdyn::api;

// As the robot does: it needs a few round trips before it calls its estimate good.
constexpr int kSamplesForOk = 3;
constexpr size_t kMaxClocks = 64;  // clients that went away are forgotten, oldest first

bool complete(const api::TimeSyncRoundTrip& t) {
  return t.has_client_tx() && t.has_server_rx() && t.has_server_tx() && t.has_client_rx();
}

// NTP's arithmetic: the network delay without the robot's time in between, and the offset
// that puts the robot's receive and send halfway along the client's round trip.
api::TimeSyncEstimate estimate(const api::TimeSyncRoundTrip& t) {
  const int64_t c_tx = TimeUtil::TimestampToNanoseconds(t.client_tx());
  const int64_t s_rx = TimeUtil::TimestampToNanoseconds(t.server_rx());
  const int64_t s_tx = TimeUtil::TimestampToNanoseconds(t.server_tx());
  const int64_t c_rx = TimeUtil::TimestampToNanoseconds(t.client_rx());
  api::TimeSyncEstimate e;
  *e.mutable_round_trip_time() = TimeUtil::NanosecondsToDuration((c_rx - c_tx) - (s_tx - s_rx));
  *e.mutable_clock_skew() = TimeUtil::NanosecondsToDuration(((s_rx - c_tx) + (s_tx - c_rx)) / 2);
  return e;
}

}  // namespace

grpc::Status TimeSyncService::TimeSyncUpdate(grpc::ServerContext* ctx, const api::TimeSyncUpdateRequest* request,
                                             api::TimeSyncUpdateResponse* response) {
  if (auto status = admit_call(robot_, *ctx, Token::kRequired); !status.ok()) return status;
  const ReturnTrip return_trip(robot_);  // the answer travels back after it is stamped
  const auto received = now_timestamp();
  fill_response_header(request->header(), received, response->mutable_header());
  std::lock_guard lock(mutex_);
  std::string id = request->clock_identifier();
  if (id.empty() || !clocks_.count(id)) {
    if (clocks_.size() >= kMaxClocks) {
      auto oldest = clocks_.begin();
      for (auto it = clocks_.begin(); it != clocks_.end(); ++it) {
        if (it->second.last_used < oldest->second.last_used) oldest = it;
      }
      clocks_.erase(oldest);
    }
    if (id.empty()) id = "spot-mock-clock-" + std::to_string(next_id_);
    clocks_[id];
  }
  Clock& clock = clocks_[id];
  clock.last_used = next_id_++;
  if (complete(request->previous_round_trip())) {
    const api::TimeSyncEstimate e = estimate(request->previous_round_trip());
    *response->mutable_previous_estimate() = e;
    ++clock.samples;
    if (clock.samples == 1 || e.round_trip_time() < clock.best.round_trip_time()) clock.best = e;
  }
  auto* state = response->mutable_state();
  if (clock.samples >= kSamplesForOk) {
    state->set_status(api::TimeSyncState::STATUS_OK);
    *state->mutable_best_estimate() = clock.best;
  } else {
    state->set_status(api::TimeSyncState::STATUS_MORE_SAMPLES_NEEDED);
  }
  *state->mutable_measurement_time() = now_timestamp();
  response->set_clock_identifier(id);
  // The robot's send time goes into the client's next round trip: stamp it last.
  *response->mutable_header()->mutable_response_timestamp() = now_timestamp();
  return grpc::Status::OK;
}

}  // namespace omniview::spot_mock
