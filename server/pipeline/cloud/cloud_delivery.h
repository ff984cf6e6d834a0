// One source's coloured clouds on their way to clients. The source's render worker hands
// each frame set that carries a cloud to deliver(): the cloud is coloured with the image
// set taken nearest the middle of its sweep (this one or one of the last few), the robot's
// motion between the two times taken out when the source reports it (FrameSet::motion;
// without, the robot is assumed still), once per distinct colouring the due clients asked for (the colourer
// is rebuilt when the rig changes; points on the robot's body are flagged when the source
// has a robot model), then shaped and packed once per distinct shape the clients asked for
// and offered to each one's latest-cloud slot (cloud_subscriber.h). Nothing here waits on
// a client.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/cloud/colourer.h"
#include "core/cloud/self_filter.h"
#include "server/pipeline/cloud/cloud_subscriber.h"
#include "server/pipeline/cloud/image_history.h"
#include "server/pipeline/robot_layer.h"
#include "server/source/frame_set.h"

namespace omniview {

struct CloudDeliveryStats {
  uint64_t clouds = 0;            // clouds coloured and offered
  double last_colour_ms = 0;      // colouring one cloud (all passes), the last time
  uint64_t incomplete = 0;        // clouds skipped: a camera's image was missing
};

class CloudDelivery {
 public:
  explicit CloudDelivery(std::string source) : source_(std::move(source)) {}

  // Before the pipeline starts.
  void set_robot_model(std::shared_ptr<const RobotModelSetup> setup);

  void add(std::shared_ptr<CloudSubscriber> subscriber);
  void remove(const CloudSubscriber* subscriber);
  std::vector<std::shared_ptr<CloudSubscriber>> subscribers() const;
  size_t subscriber_count() const;
  void close_all(ErrorKind code, const std::string& reason);

  // Render worker only: every frame set of the source while someone watches its clouds,
  // so a cloud can take the image set nearest its own time (image_history.h).
  void remember(const FrameSet& frames) { history_.add(frames); }

  // Render worker only. `joints`: every model joint's position for the self-filter (null:
  // the source has no robot model).
  void deliver(const FrameSet& frames, const std::shared_ptr<const std::map<std::string, double>>& joints);

  CloudDeliveryStats stats() const;

 private:
  std::shared_ptr<const PointCloud> self_filtered(const FrameSet& frames,
                                                  const std::shared_ptr<const std::map<std::string, double>>& joints);
  // `coloured` shaped and packed as `subscriber` asked; null (and the subscriber closed)
  // when its frame is no longer connected to the cloud's.
  SharedCloud make_message(const PointCloud& coloured, const FrameSet& frames,
                           const std::shared_ptr<CloudSubscriber>& subscriber, double colour_ms);

  const std::string source_;
  std::shared_ptr<const RobotModelSetup> robot_;
  std::unique_ptr<SelfFilter> self_filter_;

  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<CloudSubscriber>> subscribers_;
  CloudDeliveryStats stats_;

  // The render worker's alone.
  std::unique_ptr<CloudColourer> colourer_;
  std::shared_ptr<const Rig> colourer_rig_;
  ImageHistory history_;
  bool warned_frame_ = false;
};

}  // namespace omniview
