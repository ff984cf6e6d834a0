// Where frame sets come from: a robot, a camera, a recording. The server knows sources only
// through this interface and the registry (source_registry.h), so adapters for Spot, the
// Insta360 Air or a lidar plug in without touching it.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "server/source/frame_set.h"

namespace omniview {

// A source's own check of one camera against its calibration (an Insta360 Air finds each
// lens's image circle in a live frame), shown per camera by ListCameras.
struct CameraCheck {
  std::string camera;
  std::string summary;   // for a person: "lens circle centre 5.1 px from the principal point ..."
  bool warning = false;  // the check says the calibration is off
};

struct SourceHealth {
  bool connected = false;
  uint64_t frames = 0;   // frame sets delivered
  uint64_t errors = 0;   // bad images/responses skipped
  std::string message;   // the last problem, for a person to read; empty when all is well
  double failure_rate = 0;  // recent failed requests to the robot, 0..1 (SourceStatus.failure_rate)
};

class Source {
 public:
  using FrameCallback = std::function<void(std::shared_ptr<const FrameSet>)>;

  virtual ~Source() = default;

  const std::string& name() const { return name_; }
  virtual std::string type() const = 0;

  // The current rig (cameras and frames). Never null once construction succeeded.
  virtual std::shared_ptr<const Rig> rig() const = 0;

  // Starts delivering frame sets to `on_frame` from the source's own thread(s). The
  // callback must return quickly (the pipeline queues and drops, it never blocks).
  virtual void start(FrameCallback on_frame) = 0;
  // Stops and joins; no callback runs after it returns. Safe to call twice.
  virtual void stop() = 0;

  // Which rig cameras some active view needs (rig order). A source that can choose what
  // to fetch (a robot over Wi-Fi) should fetch only these, and nothing when none is set.
  virtual void set_wanted_cameras(const std::vector<bool>& wanted) { (void)wanted; }

  // How coarsely the active views sample each rig camera (rig order): the typical distance
  // between neighbouring view samples in that camera's image, as a fraction of the image's
  // width; 0 for a camera no active view reads. A source that can deliver smaller images
  // for less work (a JPEG decoder's DCT scaling) may use it.
  virtual void set_camera_sampling(const std::vector<double>& spacing) { (void)spacing; }

  // Whether the source can deliver lidar clouds at all (StreamClouds refuses others with
  // FAILED_PRECONDITION).
  virtual bool provides_clouds() const { return false; }
  // Whether someone watches a cloud of this source. A source that can choose (a robot over
  // Wi-Fi) pulls clouds only while it is set, and attaches them to its frame sets.
  virtual void set_cloud_wanted(bool wanted) { (void)wanted; }
  // Whether a depth-aware view (`depth: measured`) of this source is watched. A source with
  // depth cameras (Spot's `*_depth_in_visual_frame`) then attaches their depth as points
  // (FrameSet::depth).
  virtual void set_depth_wanted(bool wanted) { (void)wanted; }

  // The rate the source sends frame sets at when nothing holds it back (its configured or
  // requested rate), 0 where it cannot know (a camera's own clock). A new H.264 stream
  // declares it in its SPS when the frames measured come close to it: a rate measured from a
  // few intervals on a busy machine is off by a tenth now and then.
  virtual double nominal_rate_hz() const { return 0; }

  virtual SourceHealth health() const = 0;

  // The latest checks the source made of its cameras; empty when it makes none.
  virtual std::vector<CameraCheck> camera_checks() const { return {}; }

  // The newest joint positions the source knows (a robot's own report), kept current also
  // while it delivers no frames because nobody watches; null: it reports none.
  virtual std::shared_ptr<const std::map<std::string, double>> latest_joints() const { return nullptr; }

 protected:
  explicit Source(std::string name) : name_(std::move(name)) {}

 private:
  std::string name_;
};

}  // namespace omniview
