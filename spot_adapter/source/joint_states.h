// The robot's joint positions from its robot-state service, for the robot overlay.
//
// Read beside the image calls, never waited for: a GetRobotState over a slow link must not
// hold up the images (at most one call out at a time; each image set takes the newest
// answer there is).
#pragma once

#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "bosdyn/api/robot_state_service.grpc.pb.h"
#include "spot_adapter/client/robot_session.h"

namespace omniview::spot {

using JointMap = std::map<std::string, double>;

// Every joint with a position in a robot-state answer (a joint the robot cannot measure
// right now comes without one). Throws SpotError for a header error.
std::shared_ptr<const JointMap> joints_from_robot_state(const bosdyn::api::RobotStateResponse& response);

// One GetRobotState, waited for (at connect, so the first frames already show the robot's
// pose). Throws SpotError for a failed call or a robot without that service.
std::shared_ptr<const JointMap> read_joint_states(RobotSession& session);

class JointStateReader {
 public:
  JointStateReader();
  ~JointStateReader();
  JointStateReader(const JointStateReader&) = delete;
  JointStateReader& operator=(const JointStateReader&) = delete;

  // Starts a GetRobotState on the directory's `robot-state` service unless one is out.
  // Throws SpotError(kProtocol) for a robot whose directory lists no such service.
  void request(const RobotSession& session);

  struct Answer {
    std::shared_ptr<const JointMap> joints;  // null: nothing new since the last take()
    std::string refusal;  // the robot answered but will not give joints (no such service, an error header)
  };
  Answer take();

  // Cancels a call that is out and waits until gRPC is done with it.
  void cancel();

 private:
  struct Call;
  std::mutex mutex_;
  std::condition_variable done_;
  std::unique_ptr<Call> call_;  // the call out, if any
  Answer answer_;
};

}  // namespace omniview::spot
