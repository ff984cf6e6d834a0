// The daemon's engine: sources in, views rendered and encoded, frames out to subscribers.
//
//   source thread ──deliver──▶ SourceChannel slot ──▶ render worker (one per source)
//        for each view of that source with a subscriber whose rate is due:
//          apply the view's current map → hand the image to the encoder pool, one job per
//          EncodingKey (encoder_pool.h) and go on to the next frame set
//   encoder thread: encode once per EncodingKey → offer to each subscriber's latest-frame
//          slot (never waits on a client); cheap and expensive encodings in separate lanes
//   create/update (RPC thread): build the new map there, then swap it in atomically
//   rig change (new extrinsics): a map thread rebuilds; frames keep the old map meanwhile
//   a frame set with a lidar cloud and cloud subscribers: the render worker colours it
//          with the set's images and offers it to each cloud subscriber (cloud/)
//   a frame set with a lidar cloud and watched `depth: measured` views: the cloud joins the
//          source's geometry, and a depth thread rebuilds those views' maps on it (depth/)
//
// Views without subscribers cost nothing; the source is told which cameras watched views
// need (Source::set_wanted_cameras), so a robot is asked only for those; clouds are pulled
// only while someone streams one or watches a depth view (Source::set_cloud_wanted), and
// every camera only for a coloured cloud.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "omniview/v1/omniview.pb.h"
#include "server/pipeline/errors.h"
#include "server/pipeline/cloud/cloud_delivery.h"
#include "server/pipeline/depth/depth_update_queue.h"
#include "server/pipeline/depth/source_geometry.h"
#include "server/pipeline/encoder_pool.h"
#include "server/pipeline/live_view.h"
#include "server/pipeline/pipeline_report.h"
#include "server/pipeline/robot_joints.h"
#include "server/pipeline/robot_layer.h"
#include "server/pipeline/source_channel.h"
#include "server/pipeline/subscriber.h"
#include "server/pipeline/subscription.h"

namespace omniview {

struct Staleness;

struct PipelineLimits {
  int64_t max_view_pixels = 4096LL * 4096;
  int max_views = 32;
  TapLimits record_queue;  // per recording client (StreamSourceFrames)
};

// One camera of a source, as ListCameras describes it.
struct SourceCamera {
  std::string source;
  std::shared_ptr<const Rig> rig;
  size_t index = 0;  // into rig->cameras()
  std::string calibration_check;  // what the source's check of the calibration found
  bool calibration_warning = false;
};

// The ray of a view's pixel, in the robot frame (PixelToRay).
struct PixelRay {
  std::string robot_frame;
  Vec3 origin = Vec3::Zero();
  bool valid = false;  // the pixel has a ray (a fisheye view's corners do not)
  Vec3 direction = Vec3::Zero(), direction_view = Vec3::Zero();  // unit; robot and view frame
  std::optional<Vec3> surface_point;  // where the ray meets the view's surface (robot frame)
};

class Pipeline {
 public:
  explicit Pipeline(PipelineLimits limits = {});
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Before start(). The first source added is the default for views that name none.
  void add_source(std::unique_ptr<Source> source);
  // The robot drawn into `source`'s views that ask for it (overlay on). Before start().
  void set_robot_model(const std::string& source, std::shared_ptr<const RobotModelSetup> setup);
  void start();
  // Ends every stream with `reason`, stops the sources and joins all threads. Idempotent.
  void stop(const std::string& reason);

  // All of these throw PipelineError (NOT_FOUND, INVALID_ARGUMENT, ALREADY_EXISTS, ...).
  // Every camera of `source` ("" = all sources), with its calibration check.
  std::vector<SourceCamera> cameras(const std::string& source) const;
  // A view's description is the wire's v1::View on purpose: it is made once per revision
  // and rides in every frame of the view (v1::Frame.camera), which every client of every
  // front end shares by pointer.
  v1::View create_view(ViewSpec spec);
  // `change` edits a copy of the view's spec (a front end's patch and joystick step);
  // std::invalid_argument from it is INVALID_ARGUMENT.
  v1::View update_view(const std::string& name, const std::function<void(ViewSpec&)>& change);
  void delete_view(const std::string& name);
  v1::View get_view(const std::string& name) const;
  std::vector<v1::View> list_views() const;
  PixelRay pixel_to_ray(const std::string& view, double u, double v) const;
  // Where `point` (in `frame`, "" = the robot frame) appears in the view; nullopt where it
  // does not (behind the view, outside its image).
  std::optional<Vec2> point_to_pixel(const std::string& view, const Vec3& point, const std::string& frame) const;

  // `stale_frames`: the client wants its view's last picture again, marked, while the
  // source is silent (staleness.h).
  // Each stream is held by a Subscription, which leaves the pipeline when it ends.
  ViewSubscription subscribe(const std::string& view, const std::string& peer, EncodingKey key, double max_rate_hz,
                             bool stale_frames = false);
  // Every frame set of `source` into a bounded queue (a recording). A passive tap (the black
  // box) keeps what flows for the views anyway and asks the source for nothing more; an
  // active one makes it deliver every camera at full resolution.
  TapSubscription tap(const std::string& source, bool passive = false, TapLimits limits = {});
  // Coloured clouds of `source` ("" = default) as `request` asks: NOT_FOUND for an unknown
  // source, FAILED_PRECONDITION for one without clouds, INVALID_ARGUMENT for a frame the
  // source's rig lacks.
  CloudSubscription subscribe_cloud(const std::string& source, const std::string& peer, CloudRequest request,
                                    double max_rate_hz);
  // Whether `source` ("" = default) delivers lidar clouds (NOT_FOUND for an unknown source).
  bool provides_clouds(const std::string& source) const;
  // The rig a source currently delivers (for recordings).
  std::shared_ptr<const Rig> rig(const std::string& source) const;

  // Sources, views, clients and the cameras being pulled, now (GetStatus).
  PipelineReport report() const;
  // What `source` ("" = default) says of itself now (connected, its last problem).
  SourceHealth source_health(const std::string& source) const;
  // The robot overlay's joints of `source` ("" = default): set through the API, and read.
  JointsReport set_joint_positions(const std::string& source, const JointMap& positions, bool clear);
  JointsReport joint_positions(const std::string& source) const;
  bool stopped() const { return stopped_; }

 private:
  // What a Subscription's end calls.
  void unsubscribe(const std::string& view, const Subscriber* subscriber);
  void untap(const std::string& source, const FrameSetTap* tap);
  void unsubscribe_cloud(const std::string& source, const CloudSubscriber* subscriber);
  std::shared_ptr<LiveView> find_view(const std::string& name) const;
  SourceChannel& channel(const std::string& source) const;  // "" = default source
  std::shared_ptr<const ViewState> build_state(const ViewSpec& spec, uint64_t revision) const;
  void update_wanted_cameras(const std::string& source);
  void render_worker(SourceChannel* channel);
  // `staleness`: set when re-rendering a silent source's last images (staleness.h).
  void render_view(const std::shared_ptr<LiveView>& view, const FrameSet& frames,
                   const Staleness* staleness = nullptr);
  void resend_stale_views(SourceChannel& channel);
  void deliver_cloud(SourceChannel& channel, const FrameSet& frames);
  CloudDelivery& clouds(const std::string& source) const;  // by the source's own name
  // Measured depth (pipeline_depth.cc).
  SourceGeometry& geometry(const std::string& source) const;  // by the source's own name
  void deliver_geometry(SourceChannel& channel, const FrameSet& frames);
  bool depth_watched(const std::string& source) const;
  void update_depth(const std::string& view);
  // A depth view whose geometry is older than kFreshGeometry: back to its fixed surface.
  // Call with the view's change mutex held.
  void drop_stale_geometry(LiveView& view);
  // `state`'s view and map on `geometry` (state's rig, spec and pose set); throws
  // std::invalid_argument when the geometry's frame is not the rig's.
  void apply_measured_depth(ViewState& state, const GeometrySnapshot& geometry) const;
  DepthReport describe_depth(const ViewState& state, size_t subscribers) const;
  RobotJoints& robot_joints(const std::string& source) const;  // throws PipelineError
  void rebuild_worker();
  void request_rebuild(const std::string& view);

  const PipelineLimits limits_;
  std::vector<std::unique_ptr<SourceChannel>> channels_;
  std::map<std::string, std::shared_ptr<const RobotModelSetup>> robot_models_;  // by source; fixed after start
  std::map<std::string, std::unique_ptr<RobotJoints>> robot_joints_;            // by source; fixed after start
  std::map<std::string, std::unique_ptr<CloudDelivery>> clouds_;               // by source; fixed after start
  std::map<std::string, std::unique_ptr<SourceGeometry>> geometry_;            // by source; fixed after start
  std::unique_ptr<DepthUpdateQueue> depth_updates_;  // from start()
  std::vector<std::thread> workers_;
  std::unique_ptr<EncoderPool> encoder_;  // from start(); stopped after the render workers
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();

  mutable std::mutex views_mutex_;
  std::map<std::string, std::shared_ptr<LiveView>> views_;

  std::mutex rebuild_mutex_;
  std::condition_variable rebuild_ready_;
  std::deque<std::string> rebuild_queue_;
  std::thread rebuild_thread_;

  std::atomic<bool> started_flag_{false};
  std::atomic<bool> stopped_{false};
};

}  // namespace omniview
