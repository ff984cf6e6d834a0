// Source type `spot`: Boston Dynamics' Spot, through its own gRPC API exactly as BD's SDKs
// talk to it (TLS per authority, token login, directory). Keys: spot_settings.h.
//
// One thread per source: connect (login, robot id, directory, image sources and frame
// tree -> rig), then while some view needs cameras pull them in one GetImage per cycle at
// rate_hz, up to requests_in_flight calls overlapping (a Wi-Fi round trip is longer than a
// cycle), answers handled in order; with nobody watching nothing is pulled. While a cloud is
// wanted, each cycle also asks the lidar for one (cloud_calls.h) and attaches the newest. A robot that goes away is retried with
// a short backoff (views resume within about a second of its return); refused logins are
// retried rarely, so a wrong password never trips the robot's lockout.
#pragma once

#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include "server/source/source_registry.h"
#include "spot_adapter/client/robot_channels.h"
#include "spot_adapter/client/robot_clock.h"
#include "spot_adapter/client/robot_session.h"
#include "spot_adapter/client/spot_error.h"
#include "spot_adapter/source/cloud_calls.h"
#include "spot_adapter/source/image_calls.h"
#include "spot_adapter/source/image_set.h"
#include "spot_adapter/source/joint_states.h"
#include "spot_adapter/source/spot_settings.h"

namespace omniview::spot {

class SpotSource : public Source {
 public:
  // Reads and checks the config (no network: the robot may be away when the daemon starts).
  explicit SpotSource(const SourceConfig& config);
  ~SpotSource() override;

  std::string type() const override { return "spot"; }
  std::shared_ptr<const Rig> rig() const override;
  void start(FrameCallback on_frame) override;
  void stop() override;
  void set_wanted_cameras(const std::vector<bool>& wanted) override;
  bool provides_clouds() const override;
  void set_cloud_wanted(bool wanted) override;
  void set_depth_wanted(bool wanted) override;
  SourceHealth health() const override;
  double nominal_rate_hz() const override { return settings_.rate_hz; }
  std::shared_ptr<const std::map<std::string, double>> latest_joints() const override;

 private:
  void run();
  void connect();
  // One GetImage for `wanted`, answered later (calls_); then its images become a frame set.
  void start_call(const std::vector<size_t>& wanted);
  void finish_call(ImageCall& call);
  void refresh_tree(const std::vector<FrameEdge>& edges);
  void sync_clock();  // at connect: the robot's clock against ours (time-sync service)
  void fill_gaps(ImageSet& set, const std::vector<size_t>& wanted, std::chrono::steady_clock::time_point now);
  void set_rig(std::shared_ptr<const Rig> rig);
  void announce_rig();
  // Waits for the deadline, a change of wanted cameras or stop(); false on stop().
  bool sleep_until(std::chrono::steady_clock::time_point deadline);
  std::chrono::milliseconds on_error(const SpotError& e);
  std::vector<size_t> wanted_slots() const;
  void report(bool connected, const std::string& message);
  void log(const std::string& line) const;

  SpotSettings settings_;
  RobotChannels channels_;
  RobotSession session_;
  FrameCallback on_frame_;
  ImageCalls calls_;  // before thread_: the thread uses these until joined
  JointStateReader joint_reader_;
  CloudReader cloud_reader_;
  std::thread thread_;

  // Only the source's thread touches these.
  std::vector<CameraSlot> slots_;
  struct GoodImage {
    cv::Mat image;
    std::chrono::steady_clock::time_point time;
  };
  std::vector<GoodImage> last_good_;  // per slot, for bad images in between
  std::map<std::string, FrameEdge> tree_;  // the frame tree the current rig was built from
  uint64_t sequence_ = 0;
  int failures_ = 0;  // in a row, for the backoff
  // Each image call's outcome (failed: the call, or an image in it), averaged over the last
  // ~20: the failure rate GetStatus shows. Under mutex_ (health_ reads it).
  void count_outcome(bool failed);
  double failure_rate_ = 0;
  std::chrono::steady_clock::time_point last_outcome_;  // of the last counted call
  // The last frame set delivered, or failed call the robot answered: the robot counts as
  // connected while they keep coming within kConnectedWindow (then "degraded", not "NO").
  std::chrono::steady_clock::time_point last_answer_;
  std::chrono::steady_clock::time_point last_error_log_;
  std::string last_logged_error_;  // the same failure again is logged every kErrorLogInterval only
  std::chrono::steady_clock::time_point last_rig_change_;
  std::chrono::steady_clock::time_point last_channel_reset_;
  std::chrono::steady_clock::time_point last_depth_call_;  // the last image call that asked for depth
  std::string connect_note_;  // configured cameras the robot lacks, shown in status
  // Joint positions for the robot overlay, read at most kJointInterval apart while pulling.
  std::shared_ptr<const std::map<std::string, double>> joints_;
  Trajectory motion_;  // body in odom at each image set's capture time (body_motion.h)
  std::chrono::steady_clock::time_point joints_read_;
  void publish_joints();  // joints_ -> latest_joints_, for latest_joints()
  void refresh_idle_joints();
  // Set while nobody watches: the first frame after it reads the pose (one round trip) so
  // it never shows the legs of the last once-a-second idle read.
  bool idle_since_last_frame_ = false;
  bool robot_state_available_ = true;  // false once the robot said it has no such service
  // The robot's lidar (point_cloud_source), found at connect; empty: no clouds.
  std::string cloud_source_;
  // The newest cloud since the last image set, while one is wanted; asks for the next.
  std::shared_ptr<const PointCloud> next_cloud();
  RobotClock clock_;
  std::chrono::steady_clock::time_point clock_updated_;
  bool time_sync_available_ = true;  // false once the robot said it has no such service

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::vector<bool> wanted_;  // by rig camera (= slot) index
  bool cloud_wanted_ = false;
  bool depth_wanted_ = false;  // depth images with the images, every kDepthInterval
  bool cloud_rewanted_ = false;  // wanted again since the last cycle (next_cloud drops what is held)
  bool clouds_missing_ = false;  // connected, and the robot has no (such) point-cloud source
  std::shared_ptr<const std::map<std::string, double>> latest_joints_;
  std::shared_ptr<const Rig> rig_;
  uint64_t rig_version_ = 1;
  SourceHealth health_;
};

std::unique_ptr<Source> make_spot_source(const SourceConfig& config);

// Registers `type: spot` (the daemon calls this at start-up).
void register_spot_source();

}  // namespace omniview::spot
