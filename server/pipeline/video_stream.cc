#include "server/pipeline/video_stream.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace omniview {

double h264_crf(int quality) { return 51.0 - (quality == 0 ? kDefaultH264Quality : quality) / 2.0; }

namespace {

// The rate a new stream's SPS declares for a measured `fps`. Cameras and robots run at a
// few usual rates, and four intervals measured on a busy machine are off by several per cent
// (10.54 for a 10 Hz source): the usual rate within 8 %, else the whole number within 3 %,
// else two decimals.
double declared_rate(double fps) {
  constexpr double kUsualRates[] = {5, 7.5, 10, 12, 12.5, 15, 20, 24, 25, 30, 50, 60};
  double nearest = kUsualRates[0];
  for (const double r : kUsualRates) {
    if (std::abs(fps - r) < std::abs(fps - nearest)) nearest = r;
  }
  if (std::abs(fps - nearest) <= 0.08 * nearest) return nearest;
  const double whole = std::round(fps);
  if (whole >= 1 && std::abs(fps - whole) <= 0.03 * whole) return whole;
  return std::round(fps * 100) / 100;
}

}  // namespace

VideoStream::VideoStream(const EncodingKey& key) : key_(key) {}

bool VideoStream::take_turn(Clock::time_point now) {
  std::lock_guard lock(pace_mutex_);
  if (now < next_due_) return false;
  if (key_.rate_mhz > 0) {
    // As Subscriber::offer: from the nominal time, so jitter does not lower the rate, but
    // no backlog of turns after a pause.
    const auto period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1000.0 / key_.rate_mhz));
    next_due_ = std::max(next_due_ + period, now + period / 2);
  }
  return true;
}

void VideoStream::request_key_frame_at(uint64_t revision) {
  uint64_t asked = key_at_revision_.load();
  while (asked < revision && !key_at_revision_.compare_exchange_weak(asked, revision)) {
  }
}

video::AccessUnit VideoStream::encode(const cv::Mat& image, Clock::time_point arrival, double view_fps,
                                      uint64_t revision, double source_fps) {
  std::lock_guard lock(mutex_);
  const cv::Mat* pixels = &image;
  if (key_.gray && image.channels() == 3) {
    cv::cvtColor(image, grey_, cv::COLOR_BGR2GRAY);
    pixels = &grey_;
  }
  const auto now = Clock::now();
  // The rate frames really come at (the source's, or the group's if lower), averaged: the
  // plain mean of the first ten intervals, exponential after.
  if (last_arrival_ != Clock::time_point{} && arrival > last_arrival_) {
    const double interval = std::chrono::duration<double>(arrival - last_arrival_).count();
    const double weight = std::max(0.1, 1.0 / ++intervals_);
    mean_interval_s_ = (1 - weight) * mean_interval_s_ + weight * interval;
    if (first_intervals_.size() < 16) first_intervals_.push_back(interval);
  }
  if (first_arrival_ == Clock::time_point{}) first_arrival_ = arrival;
  last_arrival_ = arrival;
  if (!encoder_ || encoder_->settings().width != pixels->cols || encoder_->settings().height != pixels->rows) {
    double fps = view_fps;
    if (fps <= 0) {
      // One interval is noise (two frames of a burst read 34 Hz from a 15 Hz robot under
      // load, and players would run the stream twice too fast): four, or a second's worth.
      const bool known = intervals_ >= kRateIntervals || (intervals_ > 0 && arrival - first_arrival_ >= kRateWindow);
      if (!known) return {};  // the next frames tell the rate
      // The median, not the mean: one frame late by 40 ms shortened four intervals' span
      // by a tenth, and a 10 Hz stream declared 12 (the CI rehearsal of stop 32).
      std::vector<double> sorted = first_intervals_;
      std::sort(sorted.begin(), sorted.end());
      const size_t n = sorted.size();
      fps = 2.0 / (sorted[(n - 1) / 2] + sorted[n / 2]);
    }
    if (source_fps > 0 && fps >= kNominalShare * source_fps) fps = source_fps;
    if (key_.rate_mhz > 0) fps = std::min(fps, key_.rate_mhz / 1000.0);
    video::H264Settings settings;
    settings.width = pixels->cols;
    settings.height = pixels->rows;
    settings.fps = std::clamp(declared_rate(fps), 0.1, 120.0);
    settings.crf = h264_crf(key_.quality);
    settings.max_kbps = key_.max_kbps;
    encoder_.reset();  // the old one's memory first
    encoder_ = std::make_unique<video::H264Encoder>(settings);
    key_wanted_ = true;  // a new size starts with a key frame (new SPS) for everyone
  }
  bool key = false;
  // Not for a frame of an older revision (still in flight when the view changed): the
  // clients that asked refuse that one and wait for the key frame of the new view.
  uint64_t key_at = key_at_revision_.load();
  if (key_at != 0 && revision >= key_at) {
    key = true;
    key_at_revision_.compare_exchange_strong(key_at, 0);  // a later revision's ask stays
  }
  if (key_wanted_ && (last_key_ == Clock::time_point{} || now - last_key_ >= kMinKeyInterval)) key = true;
  if (now - last_key_ >= kMaxKeyInterval) key = true;
  if (mean_interval_s_ > 0) encoder_->set_frame_rate(1.0 / mean_interval_s_);
  const auto pts_ms = std::chrono::duration_cast<std::chrono::milliseconds>(arrival.time_since_epoch()).count();
  video::AccessUnit au = encoder_->encode(*pixels, pts_ms, key);
  if (au.key_frame) {
    last_key_ = now;
    key_wanted_ = false;
  }
  return au;
}

void VideoStream::keep_key_frame(SharedFrame frame) {
  std::lock_guard lock(key_frame_mutex_);
  last_key_frame_ = std::move(frame);
  last_key_frame_at_ = Clock::now();
}

std::pair<SharedFrame, VideoStream::Clock::time_point> VideoStream::last_key_frame() const {
  std::lock_guard lock(key_frame_mutex_);
  return {last_key_frame_, last_key_frame_at_};
}

}  // namespace omniview
