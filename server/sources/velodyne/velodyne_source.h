// Source type `velodyne`: a robot's own Velodyne VLP-16, paired with the camera source that
// colours its clouds. The camera source is written inside it (`cameras:`), so the pair is
// one source to the pipeline: its frame sets are the camera source's, each full rotation
// attached as the cloud of the next frame set, and its rig is the camera rig plus the
// lidar's frame.
//
//   - name: rig
//     type: velodyne
//     cameras: {type: images, rig: rig.yaml, images: {...}}   # any camera source's keys
//     bind: 127.0.0.1        # default loopback; the lidar's network: that interface's address
//     port: 2368             # the VLP-16's data port (0: a free one)
//     sender: 192.168.1.201  # optional: only packets from the lidar's address
//     frame: velodyne        # the cloud's frame, added to the camera rig
//     parent: base_link      # default: the camera rig's own frame
//     pose: [x, y, z, yaw, pitch, roll]     # the lidar in `parent` (m, deg)
//     calibration: {elevation_deg: [16 angles], min_range_m: 0.4, max_range_m: 130}
//     returns: all           # dual-return packets: all, strongest or last
//     point_time: true       # each point's firing time (seconds after the cloud's stamp)
//
// The socket is bound when the source starts, and again every second until that works (the
// lidar's interface may come up after the daemon; status says why meanwhile); it is always
// read, so no stale packets pile up in the kernel, and packets are decoded only while
// someone watches the source's cloud. Bad packets (size, block flag, azimuth, return mode, wrong
// sender) are counted and skipped: status shows the counts in the source's message.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <thread>

#include "server/source/source_registry.h"
#include "server/sources/velodyne/udp_listener.h"
#include "server/sources/velodyne/velodyne_settings.h"

namespace omniview {

class VelodyneSource : public Source {
 public:
  explicit VelodyneSource(const SourceConfig& config);
  ~VelodyneSource() override;

  std::string type() const override { return "velodyne"; }
  std::shared_ptr<const Rig> rig() const override;
  void start(FrameCallback on_frame) override;
  void stop() override;
  void set_wanted_cameras(const std::vector<bool>& wanted) override { cameras_->set_wanted_cameras(wanted); }
  void set_camera_sampling(const std::vector<double>& spacing) override { cameras_->set_camera_sampling(spacing); }
  bool provides_clouds() const override { return true; }
  void set_cloud_wanted(bool wanted) override { cloud_wanted_ = wanted; }
  SourceHealth health() const override;
  std::vector<CameraCheck> camera_checks() const override { return cameras_->camera_checks(); }
  std::shared_ptr<const std::map<std::string, double>> latest_joints() const override {
    return cameras_->latest_joints();
  }

 private:
  void receive_loop();
  void on_camera_frames(const std::shared_ptr<const FrameSet>& frames, const FrameCallback& on_frame);
  // The camera rig with the lidar's frame added (cached per camera rig).
  std::shared_ptr<const Rig> with_lidar(const std::shared_ptr<const Rig>& camera_rig) const;

  VelodyneSettings settings_;
  std::unique_ptr<Source> cameras_;
  std::atomic<bool> cloud_wanted_{false};
  std::atomic<bool> stopping_{false};
  std::thread receiver_;

  mutable std::mutex rig_mutex_;
  mutable std::shared_ptr<const Rig> camera_rig_seen_, rig_;
  mutable uint64_t rig_version_ = 0;

  mutable std::mutex mutex_;                   // guards what follows
  std::shared_ptr<const PointCloud> pending_;  // the newest rotation no frame set carried yet
  uint64_t packets_ = 0, bad_packets_ = 0, rotations_ = 0;
  std::string last_problem_;
  bool lidar_clock_synchronised_ = true;  // the lidar's own packet times agree with ours
  double lidar_clock_correction_s_ = 0;   // how far they are moved when they do not
  std::string listen_problem_;  // why the socket cannot be bound (yet); empty once it is
};

std::unique_ptr<Source> make_velodyne_source(const SourceConfig& config);

}  // namespace omniview
