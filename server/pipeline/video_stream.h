// The one H.264 encoder that every client of a view's (encoding key, rate) group shares.
//
// Video is stateful: each frame is coded against the ones before, so a group's frames go
// through one persistent encoder in order (the encoder pool runs at most one job per group
// at a time) and every subscriber of the group gets the same access units. The group keeps
// its own pace (`take_turn`), not each client's. The encoder lives as long as some
// subscriber holds the stream (LiveView::join_video hands it out and forgets it once the
// last one is gone), and is made again when the view's size changes (the next frame is
// a key frame with the new SPS).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <opencv2/core/mat.hpp>
#include <utility>
#include <vector>

#include "server/pipeline/subscriber.h"
#include "server/video/h264_encoder.h"

namespace omniview {

class VideoStream {
 public:
  using Clock = std::chrono::steady_clock;
  // Forced key frames come at most this often: a client that keeps missing frames cannot
  // turn everybody's stream into key frames. (A key frame is 5-10 times a frame's bits.)
  static constexpr std::chrono::milliseconds kMinKeyInterval{250};
  // A key frame at least this often even when nobody asks (a decoder that lost its way
  // recovers by itself).
  static constexpr std::chrono::seconds kMaxKeyInterval{10};
  // A stream that measures its own rate declares it after this many frame intervals, or
  // after this long for a slow view (~270 ms at 15 Hz before its first frame).
  static constexpr int kRateIntervals = 4;
  static constexpr std::chrono::seconds kRateWindow{1};
  // A measured rate at least this share of the source's nominal one declares the nominal.
  static constexpr double kNominalShare = 0.8;

  explicit VideoStream(const EncodingKey& key);

  const EncodingKey& key() const { return key_; }

  // Render thread: whether the group is due a frame at its rate; if so, its turn is taken.
  bool take_turn(Clock::time_point now);
  // The frame rate the stream's SPS declares (0: no encoder yet). For tests and status.
  double declared_fps() const {
    std::lock_guard lock(mutex_);
    return encoder_ ? encoder_->settings().fps : 0;
  }
  // Any thread: the next frame encoded is a key frame (or the first after kMinKeyInterval).
  void request_key_frame() { key_wanted_ = true; }
  // Any thread: the first frame of view revision `revision` or later is a key frame, at
  // once (a client lost a frame of the view's previous revision: it resumes there).
  void request_key_frame_at(uint64_t revision);

  // Encoder thread: `image` (grey or BGR; made grey for a gray key) as the next access unit.
  // `view_fps` is the rate the view's frames come at now, averaged since its last pause (0:
  // not known yet). The stream's SPS declares its frame rate (players time a raw stream by
  // it), so a new encoder takes the view's rate, capped by the group's and rounded to the
  // whole number within 3 %; without it, the stream measures the rate itself
  // over its first kRateIntervals intervals (or kRateWindow), and until then each frame
  // only times the rate and an empty access unit comes back (nothing to send).
  // `source_fps` is the source's nominal rate (Source::nominal_rate_hz, 0: unknown): a rate
  // measured within kNominalShare of it is that rate exactly (a few intervals on a busy
  // machine read 12 Hz from a 10 Hz source); one well below it (a render that cannot keep
  // up, a robot slowed by its Wi-Fi) is declared as measured.
  // Throws std::invalid_argument where the image cannot be H.264 (an odd size), or
  // std::runtime_error if the encoder fails. `revision`: the view revision `image` shows.
  video::AccessUnit encode(const cv::Mat& image, Clock::time_point arrival, double view_fps = 0,
                           uint64_t revision = 0, double source_fps = 0);

  // The group's newest key frame, as sent, and when it was made: a new client that must
  // start at a key frame before it plays (RTSP's DESCRIBE wants the SPS/PPS for its SDP)
  // takes it at once instead of waiting up to kMinKeyInterval for the next one, on the
  // thread that serves every RTSP client. Encoder thread sets, any thread reads.
  void keep_key_frame(SharedFrame frame);
  std::pair<SharedFrame, Clock::time_point> last_key_frame() const;

 private:
  const EncodingKey key_;
  std::atomic<bool> key_wanted_{true};
  std::atomic<uint64_t> key_at_revision_{0};  // 0: none asked for
  std::mutex pace_mutex_;  // the render thread's: never waits for an encode
  Clock::time_point next_due_{};
  mutable std::mutex mutex_;  // the encoder's state (the pool runs one job per group at a time anyway)
  std::unique_ptr<video::H264Encoder> encoder_;
  Clock::time_point last_key_{};
  Clock::time_point first_arrival_{};
  Clock::time_point last_arrival_{};
  int intervals_ = 0;
  double mean_interval_s_ = 0;
  std::vector<double> first_intervals_;  // the first few, whose median a new stream declares
  cv::Mat grey_;
  mutable std::mutex key_frame_mutex_;
  SharedFrame last_key_frame_;
  Clock::time_point last_key_frame_at_{};
};

// H264 quality 1..100 (0: default) -> x264's constant rate factor: CRF = 51 - quality / 2,
// so 100 is CRF 1 and the default 50 is CRF 26: ~41 dB on spot-mock's room at a third of a
// megabit a second for the front view (bench/README.md).
double h264_crf(int quality);
constexpr int kDefaultH264Quality = 50;

}  // namespace omniview
