// Coloured clouds: who watches a source's cloud, and handing each cloud the source delivers
// to its CloudDelivery (cloud/cloud_delivery.h) on the source's render worker.
#include "server/pipeline/pipeline.h"

namespace omniview {

CloudDelivery& Pipeline::clouds(const std::string& source) const { return *clouds_.at(source); }

bool Pipeline::provides_clouds(const std::string& source) const { return channel(source).source().provides_clouds(); }

CloudSubscription Pipeline::subscribe_cloud(const std::string& source, const std::string& peer, CloudRequest request,
                                            double max_rate_hz) {
  if (stopped_) throw PipelineError(ErrorKind::kUnavailable, "omniviewd is shutting down");
  SourceChannel& ch = channel(source);  // NOT_FOUND for an unknown source
  const std::string name = ch.source().name();
  if (!ch.source().provides_clouds()) {
    throw PipelineError(ErrorKind::kFailedPrecondition,
                        "source '" + name + "' (type " + ch.source().type() + ") delivers no point clouds");
  }
  if (!request.frame.empty()) {
    const auto r = rig(name);
    if (!r->frames().has_frame(request.frame)) {
      std::string known;
      for (const auto& f : r->known_frames()) known += (known.empty() ? "" : ", ") + f;
      throw PipelineError(ErrorKind::kInvalidArgument,
                          "options.frame: '" + request.frame + "' is not a frame of source '" + name +
                              "' (frames: " + known + ")");
    }
  }
  auto s = std::make_shared<CloudSubscriber>(peer, std::move(request), max_rate_hz);
  clouds(name).add(s);
  CloudSubscription held(s, [this, name](const CloudSubscriber* left) { unsubscribe_cloud(name, left); });
  update_wanted_cameras(name);
  return held;
}

void Pipeline::unsubscribe_cloud(const std::string& source, const CloudSubscriber* subscriber) {
  const std::string name = channel(source).source().name();
  clouds(name).remove(subscriber);
  update_wanted_cameras(name);
}

void Pipeline::deliver_cloud(SourceChannel& ch, const FrameSet& frames) {
  const std::string& name = ch.source().name();
  CloudDelivery& delivery = clouds(name);
  if (delivery.subscriber_count() == 0) return;
  // A new rig (a robot that just connected) may bring new cameras: ask for all of them.
  if (frames.rig && frames.rig != ch.cloud_rig_seen()) {
    ch.set_cloud_rig_seen(frames.rig);
    update_wanted_cameras(name);
  }
  if (!frames.cloud) {
    delivery.remember(frames);  // its images may suit the next cloud better than that cloud's own
    return;
  }
  std::shared_ptr<const JointMap> joints;
  if (const auto it = robot_joints_.find(name); it != robot_joints_.end()) joints = it->second->effective(frames.joints);
  delivery.deliver(frames, joints);
}

}  // namespace omniview
