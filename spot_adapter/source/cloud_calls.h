// The robot's lidar clouds (point-cloud service), for coloured clouds: which source to ask
// (ListPointCloudSources at connect) and GetPointCloud calls beside the image calls.
//
// Clouds are pulled only while a cloud is wanted (Source::set_cloud_wanted), and like the
// joint angles never waited for: at most one call out at a time; each image set takes the
// newest cloud that arrived since the one before (a slow link must not hold up images).
#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>

#include "bosdyn/api/point_cloud_service.grpc.pb.h"
#include "spot_adapter/client/robot_session.h"

namespace omniview::spot {

// The point-cloud source to use: `setting` is "auto" (the first source the robot lists),
// "none" (no clouds: returns empty), or a name the robot must list. `note` receives what a
// person should know (the robot has no such source, or no point-cloud service). Throws
// SpotError for a failed call other than a missing service.
std::string find_point_cloud_source(RobotSession& session, const std::string& setting, std::string& note);

class CloudReader {
 public:
  CloudReader();
  ~CloudReader();
  CloudReader(const CloudReader&) = delete;
  CloudReader& operator=(const CloudReader&) = delete;

  // Starts a GetPointCloud of `source` unless one is out.
  void request(const RobotSession& session, const std::string& source);

  struct Answer {
    std::shared_ptr<const bosdyn::api::PointCloud> cloud;  // null: nothing new since the last take()
    std::string problem;  // the last failed answer (status, header, per-cloud status)
  };
  Answer take();

  // Cancels a call that is out and waits until gRPC is done with it.
  void cancel();

 private:
  struct Call;
  std::mutex mutex_;
  std::condition_variable done_;
  std::unique_ptr<Call> call_;
  Answer answer_;
};

}  // namespace omniview::spot
