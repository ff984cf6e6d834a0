// One view the daemon keeps: its definition, its current map, and who watches it.
//
// The map is immutable once built and held by shared_ptr: a rebuild makes a new one and
// swaps the pointer under the lock, so a frame being rendered keeps the map it started
// with and nothing on the hot path waits for a rebuild.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/depth/measured_depth_view.h"
#include "core/gain/gain_compensator.h"
#include "core/map/fusion_map.h"
#include "core/rig/rig.h"
#include "core/view/view.h"
#include "omniview/v1/omniview.pb.h"
#include "server/pipeline/robot_layer.h"
#include "server/pipeline/subscriber.h"

namespace omniview {

// A view with `depth: measured`: the surface its map stands on, and the geometry it came from.
struct ViewDepth {
  std::shared_ptr<const DepthSurface> surface;  // the view's rays and fixed surface (per revision)
  std::shared_ptr<const FeatherSet> feathers;   // blend: the rig cameras' weights, made once per revision
  uint64_t geometry_version = 0;                // of the geometry the map stands on; 0: none yet
  std::chrono::steady_clock::time_point geometry_arrival{};  // its newest cloud's: the age shown
  std::chrono::steady_clock::time_point geometry_ready{};    // freshness counts from here
  double measured_fraction = 0;                 // of the view's pixels on measured depth
  double update_ms = 0;                         // the last update: surface, occlusion and map
};

// Everything one revision of a view needs to render and describe itself. A depth view's
// map changes within a revision, as its geometry does: a new state with the same revision.
struct ViewState {
  ViewSpec spec;
  uint64_t revision = 0;
  std::shared_ptr<const View> view;
  std::shared_ptr<const Rig> rig;  // the rig `map` was built for (a new rig object: rebuild)
  std::shared_ptr<const FusionMap> map;
  double build_ms = 0;
  double coverage = 0;  // of `map`: computed once, sent with every frame
  Pose T_robot_view = Pose::Identity();  // the view frame in the rig's default frame
  std::shared_ptr<const v1::View> description;  // as sent with every frame
  std::shared_ptr<const ViewDepth> depth;        // null: a fixed surface
};

struct ViewStats {
  uint64_t frames = 0;
  uint64_t map_rebuilds = 0;
  uint64_t depth_updates = 0;  // maps rebuilt for new geometry (depth: measured)
  double last_map_build_ms = 0;
  double fps = 0;  // 1 / the exponentially averaged frame interval, since the view's last pause
  double mean_interval_s = 0;
  // Frames since the average started again: the view was watched again after nobody did,
  // or its source resumed after a stall. The idle gap is no frame interval, and folded
  // into the average it made a view's rate read 1-7 Hz for a 10 Hz source (issue 29).
  uint64_t run_frames = 0;
  double last_latency_ms = 0;
  std::chrono::steady_clock::time_point last_frame{};
};

class LiveView {
 public:
  explicit LiveView(std::shared_ptr<const ViewState> state) : state_(std::move(state)) {}

  std::shared_ptr<const ViewState> state() const {
    std::lock_guard lock(mutex_);
    return state_;
  }
  void set_state(std::shared_ptr<const ViewState> state) {
    std::lock_guard lock(mutex_);
    state_ = std::move(state);
  }
  // Serialises changes to one view (two joysticks, or a rig rebuild during an update).
  std::mutex& change_mutex() { return change_mutex_; }

  void add_subscriber(std::shared_ptr<Subscriber> s);
  void remove_subscriber(const Subscriber* s);
  std::vector<std::shared_ptr<Subscriber>> subscribers() const;
  size_t subscriber_count() const;
  // When the view last went from no subscriber to one: a source asked for images only from
  // then on (Spot pulls nothing while nobody watches) is not stale before it had time.
  std::chrono::steady_clock::time_point watched_since() const;
  void close_all(ErrorKind code, const std::string& reason);
  // The shared encoder of this view's video group `key` (video_stream.h): the one its
  // subscribers hold, or a new one when nobody holds it any more.
  std::shared_ptr<VideoStream> join_video(const EncodingKey& key);

  // The view's robot layer (views with overlay on), made on first use and kept across
  // revisions, so a robot that did not move is not drawn again.
  ViewOverlay& overlay(const std::shared_ptr<const RobotModelSetup>& setup);

  // The gains to render `images` with (core/gain): estimated from them over the map's
  // overlap and smoothed over this view's frames, across revisions (exposure belongs to the
  // cameras, not to the view's pose). Empty where the map has no overlap samples.
  CameraGains update_gains(const FusionMap& map, const std::vector<cv::Mat>& images, int channels);

  void record_map_build(double ms);
  void record_depth_update();
  void record_frame(double latency_ms, std::chrono::steady_clock::time_point now);
  ViewStats stats() const;

 private:
  mutable std::mutex mutex_;
  std::mutex change_mutex_;
  std::shared_ptr<const ViewState> state_;
  std::vector<std::shared_ptr<Subscriber>> subscribers_;
  std::chrono::steady_clock::time_point watched_since_{};
  ViewStats stats_;
  std::unique_ptr<ViewOverlay> overlay_;
  // Held by the subscribers only: the encoder goes when the group's last client has left.
  std::map<EncodingKey, std::weak_ptr<VideoStream>> video_;
  // Its own lock: only the render thread takes it, almost always uncontended (a view moved
  // to another source could briefly be rendered by two).
  std::mutex gains_mutex_;
  GainCompensator gains_;
};

}  // namespace omniview
