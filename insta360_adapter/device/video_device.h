// The capture device behind the `insta360` and `v4l2` sources, as a small interface: the
// real one speaks the kernel's V4L2 API (v4l2_device.h); tests inject a fake that behaves
// like an Insta360 Air (its format list, MJPEG frames, busy, unplugged, stalled).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace omniview::insta360 {

// A V4L2 four-character code (V4L2_PIX_FMT_MJPEG is 'MJPG', YUYV is 'YUYV').
constexpr uint32_t fourcc(char a, char b, char c, char d) {
  return uint32_t(uint8_t(a)) | uint32_t(uint8_t(b)) << 8 | uint32_t(uint8_t(c)) << 16 | uint32_t(uint8_t(d)) << 24;
}
inline constexpr uint32_t kMjpeg = fourcc('M', 'J', 'P', 'G');
inline constexpr uint32_t kYuyv = fourcc('Y', 'U', 'Y', 'V');
std::string fourcc_text(uint32_t code);

// One size of one pixel format the device offers, with its frame rates.
struct FormatOption {
  uint32_t pixel_format = 0;
  int width = 0, height = 0;
  std::vector<double> fps;  // discrete rates the device lists (may be empty: unknown)
};
std::string describe(const FormatOption& option);                // "MJPG 3008x1504 @ 30/15 fps"
std::string describe(const std::vector<FormatOption>& options);  // one per line

struct CaptureFormat {
  uint32_t pixel_format = 0;
  int width = 0, height = 0;
  double fps = 0;
  int bytes_per_line = 0;  // raw formats: row pitch in bytes
};

struct CapturedFrame {
  std::vector<uint8_t> bytes;  // MJPEG: one JPEG; YUYV: rows of bytes_per_line
  uint64_t sequence = 0;       // the driver's frame counter (gaps: frames it dropped)
  // When the driver captured it, on CLOCK_MONOTONIC (the kernel's V4L2 timestamps with
  // V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC, which UVC sets); zero when the driver gave none.
  std::chrono::nanoseconds monotonic_time{0};
  std::chrono::steady_clock::time_point dequeued;  // when we had it
};

enum class DeviceFault {
  kNotFound,      // no such device (yet): unplugged or never there
  kBusy,          // another program holds it
  kPermission,    // the daemon's user may not open it
  kDisconnected,  // gone while streaming (unplugged)
  kNoFormat,      // it offers nothing we can use / nothing matching the request
  kNotCapture,    // not a video capture device
  kIo,            // anything else the kernel said
};

class DeviceError : public std::runtime_error {
 public:
  DeviceError(DeviceFault fault, const std::string& what) : std::runtime_error(what), fault_(fault) {}
  DeviceFault fault() const { return fault_; }

 private:
  DeviceFault fault_;
};

class VideoDevice {
 public:
  virtual ~VideoDevice() = default;
  // "/dev/video2 (Insta360 Air)"
  virtual std::string name() const = 0;
  virtual std::vector<FormatOption> formats() = 0;
  // Sets the format and rate and starts streaming; returns what the driver agreed to.
  virtual CaptureFormat start(const CaptureFormat& wanted) = 0;
  // Waits up to `timeout` for the next frame: false on timeout (a stalled stream). Throws
  // DeviceError (kDisconnected when unplugged).
  virtual bool next_frame(std::chrono::milliseconds timeout, CapturedFrame& frame) = 0;
};

// Opens the device the config names (see device_locator.h); throws DeviceError.
using DeviceOpener = std::function<std::unique_ptr<VideoDevice>()>;

}  // namespace omniview::insta360
