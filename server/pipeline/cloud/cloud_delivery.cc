#include "server/pipeline/cloud/cloud_delivery.h"

#include <algorithm>
#include <chrono>
#include <iostream>

#include <opencv2/imgproc.hpp>

#include "server/pipeline/cloud/cloud_message.h"

namespace omniview {
namespace {

using Clock = std::chrono::steady_clock;

// The frames a rig knows, for an error a person can act on.
std::string frame_list(const Rig& rig) {
  std::string out;
  for (const auto& f : rig.known_frames()) out += (out.empty() ? "" : ", ") + f;
  return out;
}

}  // namespace

void CloudDelivery::set_robot_model(std::shared_ptr<const RobotModelSetup> setup) {
  robot_ = std::move(setup);
  self_filter_ = robot_ && robot_->model ? std::make_unique<SelfFilter>(*robot_->model) : nullptr;
}

void CloudDelivery::add(std::shared_ptr<CloudSubscriber> subscriber) {
  std::lock_guard lock(mutex_);
  subscribers_.push_back(std::move(subscriber));
}

void CloudDelivery::remove(const CloudSubscriber* subscriber) {
  std::lock_guard lock(mutex_);
  std::erase_if(subscribers_, [&](const auto& s) { return s.get() == subscriber; });
}

std::vector<std::shared_ptr<CloudSubscriber>> CloudDelivery::subscribers() const {
  std::lock_guard lock(mutex_);
  return subscribers_;
}

size_t CloudDelivery::subscriber_count() const {
  std::lock_guard lock(mutex_);
  return subscribers_.size();
}

void CloudDelivery::close_all(ErrorKind code, const std::string& reason) {
  for (const auto& s : subscribers()) s->close(code, reason);
}

CloudDeliveryStats CloudDelivery::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

std::shared_ptr<const PointCloud> CloudDelivery::self_filtered(
    const FrameSet& frames, const std::shared_ptr<const std::map<std::string, double>>& joints) {
  if (!self_filter_ || !joints) return frames.cloud;
  const Rig& rig = *frames.rig;
  const std::string root = robot_->frame.empty() ? rig.default_frame() : robot_->frame;
  const auto T_root_cloud = rig.frames().try_lookup(root, frames.cloud->frame);
  if (!T_root_cloud) return frames.cloud;  // the colourer reports the unconnected frame
  std::vector<double> positions = robot_->model->zero_positions();
  robot_->model->apply(*joints, positions);
  auto marked = std::make_shared<PointCloud>(*frames.cloud);
  self_filter_->mark(*marked, positions, *T_root_cloud);
  return marked;
}

void CloudDelivery::deliver(const FrameSet& frames,
                            const std::shared_ptr<const std::map<std::string, double>>& joints) {
  if (!frames.cloud || !frames.rig) return;
  remember(frames);
  const auto now = Clock::now();
  std::vector<std::shared_ptr<CloudSubscriber>> due;
  for (const auto& s : subscribers()) {
    if (s->due(now)) due.push_back(s);
  }
  if (due.empty()) return;
  const Rig& rig = *frames.rig;

  // The complete image set (a camera missing, as when wanted cameras just changed, would
  // leave its part of the cloud uncoloured) taken nearest the cloud's own time.
  const FrameSet* taken = history_.nearest(cloud_mid_time(*frames.cloud), frames.rig);
  if (!taken) {
    std::lock_guard lock(mutex_);
    ++stats_.incomplete;
    return;
  }
  // Every camera's image at its calibrated size (a source may have decoded smaller ones
  // for the views), stamped with its set's capture time for the time sync.
  CameraImages images;
  images.images.resize(rig.cameras().size());
  images.stamps.assign(rig.cameras().size(), taken->capture_time);
  for (size_t i = 0; i < rig.cameras().size(); ++i) {
    const Camera& c = rig.cameras()[i];
    const cv::Mat& img = taken->images[i];
    if (img.cols == c.width && img.rows == c.height) {
      images.images[i] = img;
    } else {
      cv::resize(img, images.images[i], cv::Size(c.width, c.height), 0, 0, cv::INTER_LINEAR);
    }
  }
  if (colourer_rig_ != frames.rig) {
    colourer_ = std::make_unique<CloudColourer>(frames.rig);
    colourer_rig_ = frames.rig;
  }
  std::shared_ptr<const PointCloud> input;
  try {
    input = self_filtered(frames, joints);
  } catch (const std::exception& e) {
    std::cerr << "omniviewd: source '" << source_ << "': clouds not self-filtered: " << e.what() << "\n";
    input = frames.cloud;
  }

  // One colouring pass per distinct colouring asked for (usually one).
  while (!due.empty()) {
    const auto first = due.front();
    std::vector<std::shared_ptr<CloudSubscriber>> group;
    std::erase_if(due, [&](const auto& s) {
      if (!s->request().same_colouring(first->request())) return false;
      group.push_back(s);
      return true;
    });
    PointCloud coloured = *input;
    const auto t0 = Clock::now();
    try {
      colourer_->colour(coloured, images, first->request().colour_options(), frames.motion.get());
    } catch (const std::invalid_argument& e) {
      // The cloud's frame is not in the rig: nothing any client could fix by asking again.
      const std::string reason = "source '" + source_ + "' cannot colour its cloud: " + e.what();
      if (!warned_frame_) std::cerr << "omniviewd: " << reason << "\n";
      warned_frame_ = true;
      for (const auto& s : group) s->close(ErrorKind::kFailedPrecondition, reason);
      continue;
    }
    const double colour_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    {
      std::lock_guard lock(mutex_);
      ++stats_.clouds;
      stats_.last_colour_ms = colour_ms;
    }
    // One message per distinct shape asked for, shared by the clients that asked it.
    std::vector<std::pair<const CloudRequest*, SharedCloud>> made;
    for (const auto& s : group) {
      const auto it = std::find_if(made.begin(), made.end(),
                                   [&](const auto& m) { return m.first->same_shape(s->request()); });
      if (it != made.end()) {
        s->offer(it->second, Clock::now());
        continue;
      }
      if (SharedCloud message = make_message(coloured, frames, s, colour_ms)) {
        s->offer(message, Clock::now());
        made.emplace_back(&s->request(), std::move(message));
      }
    }
  }
}

SharedCloud CloudDelivery::make_message(const PointCloud& coloured, const FrameSet& frames,
                                        const std::shared_ptr<CloudSubscriber>& subscriber, double colour_ms) {
  const Rig& rig = *frames.rig;
  const CloudRequest& request = subscriber->request();
  CloudShape shape;
  shape.frame = request.frame.empty() ? rig.default_frame() : request.frame;
  const auto T = rig.frames().try_lookup(shape.frame, coloured.frame);
  if (!T) {
    const std::string reason = "frame '" + shape.frame + "' is not connected to the cloud's frame '" +
                               coloured.frame + "' in source '" + source_ + "' (frames: " + frame_list(rig) + ")";
    subscriber->close(ErrorKind::kInvalidArgument, reason);
    return nullptr;
  }
  shape.T_out_cloud = *T;
  shape.voxel_m = request.voxel_m;
  shape.crop = request.crop;
  auto message = std::make_shared<v1::PointCloud>(pack_cloud(shape_cloud(coloured, shape)));
  message->set_source(source_);
  message->set_sequence(frames.sequence);
  message->set_input_points(coloured.size());
  for (const auto& c : rig.cameras()) message->add_cameras(c.name);
  message->set_colour_ms(colour_ms);
  message->set_latency_ms(std::chrono::duration<double, std::milli>(Clock::now() - frames.arrival).count());
  return message;
}

}  // namespace omniview
