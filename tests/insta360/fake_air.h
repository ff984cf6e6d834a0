// A fake capture device that behaves like an Insta360 Air on USB, for tests without the
// camera: the Air's format list, MJPEG frames of a dual-fisheye picture, and the faults a
// real one shows: busy (another program streams from it), unplugged mid-stream (and
// plugged back in), a stalled stream, corrupt and truncated frames.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "core/io/image_codec.h"
#include "insta360_adapter/device/video_device.h"

namespace omniview::insta360::testing {

// The Air's UVC formats as the fake lists them: MJPEG dual-fisheye frames at 2:1 sizes.
inline std::vector<FormatOption> air_formats(int width = 3008, int height = 1504) {
  return {{kMjpeg, width, height, {30, 15}}, {kMjpeg, 1920, 960, {30}}, {kMjpeg, 1472, 736, {30}}};
}

// A dual-fisheye test picture: two discs (the lens circles) on black, textured so a
// wrong crop or scale shows. `offset` moves the second disc's centre (a lens off centre).
inline cv::Mat dual_fisheye_picture(int width, int height, cv::Point2d offset = {}, double radius_fraction = 0.975) {
  cv::Mat img = cv::Mat::zeros(height, width, CV_8UC3);
  const int half = width / 2;
  for (int lens = 0; lens < 2; ++lens) {
    const cv::Point2d c = cv::Point2d(lens * half + (half - 1) / 2.0, (height - 1) / 2.0) + (lens ? offset : cv::Point2d());
    const double r = radius_fraction * half / 2;
    for (int y = 0; y < height; ++y) {
      for (int x = lens * half; x < (lens + 1) * half; ++x) {
        if (std::hypot(x - c.x, y - c.y) > r) continue;
        img.at<cv::Vec3b>(y, x) = cv::Vec3b(uchar(100 + 80 * std::sin(x * 0.05)), uchar(120 + 60 * std::cos(y * 0.07)),
                                            uchar(lens ? 200 : 90));
      }
    }
  }
  return img;
}

inline std::vector<uint8_t> jpeg_of(const cv::Mat& img, int quality = 85) { return encode_jpeg(img, quality); }

// The camera as the test drives it: plugged in or not, busy or not, and what it sends.
struct FakeAirState {
  std::mutex mutex;
  std::vector<FormatOption> formats = air_formats();
  std::vector<uint8_t> jpeg;         // sent as every frame
  bool plugged = true;
  bool busy = false;                 // start() fails as a held UVC device does
  bool stalled = false;              // plugged and streaming, but no frames come
  int corrupt_next = 0;              // that many frames are sent damaged
  bool truncate_instead = false;     // damaged = cut in half (else: bytes scrambled)
  double fps = 30;
  std::atomic<int> opens{0};
  std::atomic<uint64_t> sent{0};
  std::chrono::nanoseconds clock_skew{0};  // added to the driver timestamps

  void set(const std::function<void(FakeAirState&)>& change) {
    std::lock_guard lock(mutex);
    change(*this);
  }
};

class FakeAir : public VideoDevice {
 public:
  explicit FakeAir(std::shared_ptr<FakeAirState> state) : state_(std::move(state)) {}

  std::string name() const override { return "/dev/video-fake (Insta360 Air)"; }
  std::vector<FormatOption> formats() override {
    std::lock_guard lock(state_->mutex);
    return state_->formats;
  }
  CaptureFormat start(const CaptureFormat& wanted) override {
    std::lock_guard lock(state_->mutex);
    if (!state_->plugged) throw DeviceError(DeviceFault::kDisconnected, name() + ": unplugged (start streaming)");
    if (state_->busy) {
      throw DeviceError(DeviceFault::kBusy, name() + ": start streaming: Device or resource busy (held by pid 4242 (ffmpeg))");
    }
    next_ = std::chrono::steady_clock::now();
    return wanted;
  }
  bool next_frame(std::chrono::milliseconds timeout, CapturedFrame& frame) override {
    double fps;
    {
      std::lock_guard lock(state_->mutex);
      if (!state_->plugged) throw DeviceError(DeviceFault::kDisconnected, name() + ": unplugged (dequeue buffer)");
      fps = state_->fps;
      if (state_->stalled) {
        next_ = std::chrono::steady_clock::now();
      }
    }
    const auto now = std::chrono::steady_clock::now();
    if (next_ > now + timeout) {
      std::this_thread::sleep_for(timeout);
      return false;
    }
    {
      std::lock_guard lock(state_->mutex);
      if (state_->stalled) {
        std::this_thread::sleep_for(std::min(timeout, std::chrono::milliseconds(20)));
        return false;
      }
    }
    std::this_thread::sleep_until(next_);
    next_ += std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1 / fps));
    std::lock_guard lock(state_->mutex);
    frame.bytes = state_->jpeg;
    if (state_->corrupt_next > 0) {
      --state_->corrupt_next;
      if (state_->truncate_instead) {
        frame.bytes.resize(frame.bytes.size() / 2);
      } else {
        for (size_t i = frame.bytes.size() / 3; i < frame.bytes.size() - 2; i += 7) frame.bytes[i] ^= 0x5A;
      }
    }
    frame.sequence = state_->sent++;
    frame.dequeued = std::chrono::steady_clock::now();
    // The driver stamps the frame a few ms before we dequeue it (USB transfer).
    frame.monotonic_time = std::chrono::duration_cast<std::chrono::nanoseconds>(
                               (frame.dequeued - std::chrono::milliseconds(8)).time_since_epoch()) + state_->clock_skew;
    return true;
  }

 private:
  std::shared_ptr<FakeAirState> state_;
  std::chrono::steady_clock::time_point next_;
};

// The opener a source gets: fails like an absent device while unplugged.
inline DeviceOpener fake_air_opener(std::shared_ptr<FakeAirState> state) {
  return [state]() -> std::unique_ptr<VideoDevice> {
    ++state->opens;
    std::lock_guard lock(state->mutex);
    if (!state->plugged) throw DeviceError(DeviceFault::kNotFound, "no camera matching 'name:Insta360' is plugged in");
    return std::make_unique<FakeAir>(state);
  };
}

}  // namespace omniview::insta360::testing
