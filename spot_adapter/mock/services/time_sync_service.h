// bosdyn.api.TimeSyncService: the robot's clock against a client's, as the robot estimates
// it from the round trips the client reports (NTP's arithmetic), per clock identifier.
#pragma once

#include <map>
#include <mutex>
#include <string>

#include "bosdyn/api/time_sync_service.grpc.pb.h"
#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

class TimeSyncService final : public bosdyn::api::TimeSyncService::Service {
 public:
  explicit TimeSyncService(MockRobot& robot) : robot_(robot) {}
  grpc::Status TimeSyncUpdate(grpc::ServerContext* ctx, const bosdyn::api::TimeSyncUpdateRequest* request,
                              bosdyn::api::TimeSyncUpdateResponse* response) override;

 private:
  struct Clock {
    int samples = 0;
    bosdyn::api::TimeSyncEstimate best;  // of the fastest round trip
    int64_t last_used = 0;               // for forgetting the oldest clients
  };
  MockRobot& robot_;
  std::mutex mutex_;
  std::map<std::string, Clock> clocks_;  // by clock identifier
  int64_t next_id_ = 1;
};

}  // namespace omniview::spot_mock
