// Source type `replay`: plays back a recording (server/recording) at its original timing,
// a chosen rate, or sped up, looping by default.
//
//   - name: lab_run
//     type: replay
//     recording: recordings/lab   # folder written by `omniview record`
//     rate_hz: 15                 # optional: ignore the recorded timing
//     speed: 2.0                  # optional: factor on the recorded timing (or on rate_hz)
//     loop: true
//
// capture_time is the playback wall time, not the recorded one: the pipeline measures image
// age and latency from capture_time, and recorded times would make every frame look hours
// old (and jump back at each loop). sequence keeps increasing across loops for the same
// reason: consumers rely on it to order and drop frames.
//
// A recording that kept lidar clouds (recorded while someone watched the source's cloud)
// provides them again: each frame set carries its recorded cloud while a cloud is watched,
// its stamp moved by the same shift as the images' capture time (the lidar-to-camera
// offset stays as recorded).
#pragma once

#include <atomic>
#include <memory>
#include <mutex>

#include "server/recording/recording.h"
#include "server/source/source_registry.h"
#include "server/sources/delivery_thread.h"

namespace omniview {

class ReplaySource : public Source {
 public:
  // Opens the recording's index and rigs; throws ConfigError naming file, line and key.
  explicit ReplaySource(const SourceConfig& config);
  ~ReplaySource() override;

  std::string type() const override { return "replay"; }
  std::shared_ptr<const Rig> rig() const override;
  void start(FrameCallback on_frame) override;
  void stop() override;
  SourceHealth health() const override;
  double nominal_rate_hz() const override { return rate_hz_ * speed_; }  // 0: the recorded timing, not known ahead
  bool provides_clouds() const override { return has_clouds_; }
  void set_cloud_wanted(bool wanted) override { cloud_wanted_ = wanted; }

 private:
  void run(FrameCallback on_frame);
  // When frame `index` of the recording is due, relative to the start of its loop.
  std::chrono::steady_clock::duration offset_of(size_t index) const;
  struct Decoded {
    std::vector<cv::Mat> images;
    std::vector<EncodedImage> encoded;  // the files' bytes, per image
    std::shared_ptr<PointCloud> cloud;  // read only while a cloud is watched
  };
  // Frame `index`'s images, or none after counting a bad one in health.
  Decoded decode(size_t index);

  Recording recording_;
  double rate_hz_ = 0;  // 0: the recorded timing
  double speed_ = 1;
  bool loop_ = true;
  bool has_clouds_ = false;
  std::atomic<bool> cloud_wanted_{false};
  std::chrono::steady_clock::duration loop_length_{};
  DeliveryThread thread_;
  mutable std::mutex mutex_;  // guards current_rig_ and health_
  std::shared_ptr<const Rig> current_rig_;
  SourceHealth health_;
};

std::unique_ptr<Source> make_replay_source(const SourceConfig& config);

}  // namespace omniview
