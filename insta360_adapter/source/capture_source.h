// The daemon source behind `type: insta360` and `type: v4l2`: a capture device (a V4L2
// camera or a recording, through VideoDevice), each frame decoded once and shared by the
// rig's lens cameras (see rig/lens_layout.h), put on the daemon's clock and delivered.
//
// Faults keep the daemon running: an unplugged camera makes the source say so in its
// status and retry until it is back (then it reopens it and streams again); a busy device
// names its holder; a stalled stream is reported and, after a while, reopened; corrupt
// frames are counted and skipped.
#pragma once

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "insta360_adapter/decode/jpeg_decoder.h"
#include "insta360_adapter/device/capture_clock.h"
#include "insta360_adapter/device/format_choice.h"
#include "insta360_adapter/device/video_device.h"
#include "insta360_adapter/rig/lens_circle.h"
#include "insta360_adapter/rig/lens_layout.h"
#include "server/source/source.h"
#include "server/sources/delivery_thread.h"

namespace omniview::insta360 {

struct CaptureSettings {
  std::string type;               // "insta360" or "v4l2"
  std::string device_text;        // what the config named, for messages
  DeviceOpener open;              // throws DeviceError (kNotFound while unplugged)
  FormatRequest format;
  std::shared_ptr<const Rig> calibration;  // placed in the robot's frames, lens-image pixels
  std::vector<LensCrop> crops;
  cv::Size frame_size;            // the frame the crops are for
  int decode_scale = 0;           // 1, 2, 4; 0: the largest every active view allows
  bool check_lens_circles = false;
  std::chrono::milliseconds stall_timeout{2000};   // no frame for this long: "stalled"
  std::chrono::milliseconds reopen_after{6000};    // stalled this long: reopen the device
  std::chrono::milliseconds retry_every{1000};     // unplugged / busy: try again
};

class CaptureSource : public Source {
 public:
  CaptureSource(std::string name, CaptureSettings settings);
  ~CaptureSource() override;

  std::string type() const override { return settings_.type; }
  std::shared_ptr<const Rig> rig() const override;
  void start(FrameCallback on_frame) override;
  void stop() override;
  void set_wanted_cameras(const std::vector<bool>& wanted) override;
  // How coarsely the active views sample each camera (fraction of its image width
  // between neighbouring view samples): picks the DCT scale when decode_scale is 0.
  void set_camera_sampling(const std::vector<double>& spacing) override;
  SourceHealth health() const override;
  // The lens-circle check's latest result per lens (Air; `lens_check: true`).
  std::vector<CameraCheck> camera_checks() const override;

  // Figures beyond SourceHealth, for tests and the status message.
  struct Counters {
    uint64_t corrupt_frames = 0, opens = 0, disconnects = 0, stalls = 0, clock_fallbacks = 0;
    int decode_scale = 1;
    std::vector<LensCircleReport> lens_circles;
  };
  Counters counters() const;

  // The DCT scale for views that sample a camera every `spacing` full-resolution pixels
  // (the smallest of the active views): 4 at >= 4 px, 2 at >= 2 px, else 1.
  static int scale_for_spacing(double spacing_px);

 private:
  void run(FrameCallback on_frame);
  // Streams from an opened device until stop(), a fault (throws DeviceError) or a long
  // stall (returns).
  void stream(VideoDevice& device, const CaptureFormat& format, const FrameCallback& on_frame);
  bool deliver(const CapturedFrame& frame, const CaptureFormat& format, const FrameCallback& on_frame);
  std::shared_ptr<const Rig> rig_for_scale(int scale);
  void set_state(bool connected, const std::string& message);
  void count_error(const std::string& message);

  CaptureSettings settings_;
  DeliveryThread thread_;
  JpegDecoder decoder_;   // the capture thread's alone
  CaptureClock clock_;    // likewise

  mutable std::mutex mutex_;  // guards everything below
  std::map<int, std::shared_ptr<const Rig>> rigs_;  // per decode scale, built on first use
  std::shared_ptr<const Rig> current_rig_;
  uint64_t rig_version_ = 1;
  std::vector<bool> wanted_;
  bool wanted_known_ = false;
  int sampling_scale_ = 1;
  SourceHealth health_;
  Counters counters_;
  uint64_t sequence_ = 0;
  std::chrono::steady_clock::time_point last_lens_check_{};
};

}  // namespace omniview::insta360
