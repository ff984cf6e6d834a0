// The robot's clock against ours, from its time-sync service, as Boston Dynamics' SDKs keep
// it: each exchange reports the timestamps of the one before, and the robot answers with
// its best estimate of the offset (that of the fastest round trip). Images carry the
// robot's acquisition time; with the offset they become times on this machine's clock, so
// the frames' capture times and ages mean what they say.
#pragma once

#include <chrono>
#include <string>

#include "bosdyn/api/time_sync.pb.h"
#include "spot_adapter/client/robot_session.h"

namespace omniview::spot {

class RobotClock {
 public:
  // Exchanges until the robot reports its estimate good, at most `max_exchanges` times.
  // Throws SpotError (kProtocol for a robot without a `time-sync` service).
  void sync(RobotSession& session, int max_exchanges = 6);
  // One more exchange, to follow the clocks' drift. Throws SpotError.
  void update(RobotSession& session);
  // Forgets the estimate (a new session: the robot may have restarted).
  void reset();

  bool synced() const { return synced_; }
  // Robot clock minus ours, and the round trip it was measured over.
  std::chrono::nanoseconds skew() const { return skew_; }
  std::chrono::nanoseconds round_trip() const { return round_trip_; }
  std::chrono::system_clock::time_point to_local(std::chrono::system_clock::time_point robot_time) const {
    return robot_time - std::chrono::duration_cast<std::chrono::system_clock::duration>(skew_);
  }

 private:
  bool exchange(RobotSession& session);  // true once the robot reports STATUS_OK

  bosdyn::api::TimeSyncRoundTrip previous_;
  std::string clock_id_;
  bool synced_ = false;
  std::chrono::nanoseconds skew_{0};
  std::chrono::nanoseconds round_trip_{0};
};

}  // namespace omniview::spot
