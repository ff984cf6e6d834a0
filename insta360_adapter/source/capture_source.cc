#include "insta360_adapter/source/capture_source.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

#include <opencv2/imgproc.hpp>

#include "insta360_adapter/decode/mjpeg_stream.h"

namespace omniview::insta360 {

using Clock = std::chrono::steady_clock;

CaptureSource::CaptureSource(std::string name, CaptureSettings settings)
    : Source(std::move(name)), settings_(std::move(settings)) {
  const int scale = settings_.decode_scale > 0 ? settings_.decode_scale : 1;
  counters_.decode_scale = scale;
  // Checks the crops against the frame once, here: a config error, not a runtime one.
  current_rig_ = rig_for_scale(scale);
  health_.message = "not started";
}

CaptureSource::~CaptureSource() { stop(); }

std::shared_ptr<const Rig> CaptureSource::rig() const {
  std::lock_guard lock(mutex_);
  return current_rig_;
}

std::shared_ptr<const Rig> CaptureSource::rig_for_scale(int scale) {
  std::lock_guard lock(mutex_);
  auto& r = rigs_[scale];
  if (!r) r = std::make_shared<const Rig>(frame_rig(*settings_.calibration, settings_.crops, settings_.frame_size, scale));
  return r;
}

void CaptureSource::start(FrameCallback on_frame) {
  thread_.start([this, on_frame = std::move(on_frame)] { run(on_frame); });
}

void CaptureSource::stop() {
  thread_.stop();
  std::lock_guard lock(mutex_);
  health_.connected = false;
}

void CaptureSource::set_wanted_cameras(const std::vector<bool>& wanted) {
  std::lock_guard lock(mutex_);
  wanted_ = wanted;
  wanted_known_ = true;
}

int CaptureSource::scale_for_spacing(double spacing_px) {
  if (spacing_px >= 4) return 4;
  if (spacing_px >= 2) return 2;
  return 1;
}

void CaptureSource::set_camera_sampling(const std::vector<double>& spacing) {
  // The finest sampling of any camera decides: one frame feeds every lens.
  double finest = 0;
  for (double s : spacing) {
    if (s > 0) finest = finest == 0 ? s : std::min(finest, s);
  }
  // Nobody watching (all 0): keep the scale, so the next watcher of the same views does
  // not wait for two map rebuilds.
  if (finest == 0) return;
  std::lock_guard lock(mutex_);
  sampling_scale_ = scale_for_spacing(finest * settings_.frame_size.width);
}

SourceHealth CaptureSource::health() const {
  std::lock_guard lock(mutex_);
  return health_;
}

std::vector<CameraCheck> CaptureSource::camera_checks() const {
  std::lock_guard lock(mutex_);
  std::vector<CameraCheck> checks;
  for (const LensCircleReport& report : counters_.lens_circles) {
    std::string summary = describe(report);
    summary.erase(0, report.camera.size() + 2);  // "front: ..." -> "..."; the camera is its own column
    checks.push_back({report.camera, summary, report.found && report.offset_px > kLensOffsetWarnPx});
  }
  return checks;
}

CaptureSource::Counters CaptureSource::counters() const {
  std::lock_guard lock(mutex_);
  return counters_;
}

void CaptureSource::set_state(bool connected, const std::string& message) {
  std::lock_guard lock(mutex_);
  health_.connected = connected;
  health_.message = message;
}

void CaptureSource::count_error(const std::string& message) {
  std::lock_guard lock(mutex_);
  ++health_.errors;
  health_.message = message;
}

void CaptureSource::run(FrameCallback on_frame) {
  while (thread_.running()) {
    std::string problem;
    try {
      auto device = settings_.open();
      const CaptureFormat wanted = choose_format(device->formats(), settings_.format, device->name());
      {
        std::lock_guard lock(mutex_);
        ++counters_.opens;
      }
      const CaptureFormat got = device->start(wanted);
      if (got.width != settings_.frame_size.width || got.height != settings_.frame_size.height) {
        throw DeviceError(DeviceFault::kNoFormat, device->name() + " streams " + std::to_string(got.width) + "x" +
                                                      std::to_string(got.height) + ", the lens layout is for " +
                                                      std::to_string(settings_.frame_size.width) + "x" +
                                                      std::to_string(settings_.frame_size.height));
      }
      set_state(true, "");
      std::cerr << "omniviewd: source '" << name() << "': streaming " << fourcc_text(got.pixel_format) << " "
                << got.width << "x" << got.height << " from " << device->name() << std::endl;
      {
        std::lock_guard lock(mutex_);
        last_lens_check_ = {};  // check the lenses on the first frame of every (re)connect
      }
      stream(*device, got, on_frame);  // returns after a long stall, or when stopping
      if (!thread_.running()) return;
      problem = device->name() + ": no frames for " +
                std::to_string(settings_.reopen_after.count() / 1000.0).substr(0, 4) + " s; reopening";
    } catch (const DeviceError& e) {
      problem = e.what();
      const bool gone = e.fault() == DeviceFault::kDisconnected || e.fault() == DeviceFault::kNotFound;
      if (gone) problem = "unplugged: " + problem + "; waiting for it to come back";
      if (e.fault() == DeviceFault::kBusy) problem = "busy: " + problem;
      std::lock_guard lock(mutex_);
      if (e.fault() == DeviceFault::kDisconnected) ++counters_.disconnects;
    } catch (const std::exception& e) {
      problem = e.what();
    }
    {
      std::lock_guard lock(mutex_);
      if (health_.message != problem) std::cerr << "omniviewd: source '" << name() << "': " << problem << std::endl;
      health_.connected = false;
      health_.message = problem;
    }
    if (!thread_.wait_until(Clock::now() + settings_.retry_every)) return;
  }
}

void CaptureSource::stream(VideoDevice& device, const CaptureFormat& format, const FrameCallback& on_frame) {
  CapturedFrame frame;
  auto last_frame = Clock::now();
  bool stalled = false;
  while (thread_.running()) {
    if (!device.next_frame(std::min(settings_.stall_timeout, std::chrono::milliseconds(250)), frame)) {
      const auto quiet = Clock::now() - last_frame;
      if (quiet >= settings_.reopen_after) return;
      if (quiet >= settings_.stall_timeout && !stalled) {
        stalled = true;
        std::lock_guard lock(mutex_);
        ++counters_.stalls;
        health_.message = "stalled: " + device.name() + " sent no frame for " +
                          std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(quiet).count()) + " ms";
      }
      continue;
    }
    last_frame = Clock::now();
    if (stalled) {
      stalled = false;
      set_state(true, "");
    }
    deliver(frame, format, on_frame);
  }
}

bool CaptureSource::deliver(const CapturedFrame& frame, const CaptureFormat& format, const FrameCallback& on_frame) {
  bool any_wanted, check_lens;
  int scale;
  {
    std::lock_guard lock(mutex_);
    any_wanted = !wanted_known_ || std::find(wanted_.begin(), wanted_.end(), true) != wanted_.end();
    scale = settings_.decode_scale > 0 ? settings_.decode_scale : sampling_scale_;
    check_lens = settings_.check_lens_circles &&
                 (last_lens_check_ == Clock::time_point{} || Clock::now() - last_lens_check_ > std::chrono::seconds(60));
  }
  // Nobody watches and no check is due: the frame is not even decoded.
  if (!any_wanted && !check_lens) return false;
  const bool is_jpeg = format.pixel_format != kYuyv;
  cv::Mat image;
  if (frame.bytes.empty()) {
    std::lock_guard lock(mutex_);
    ++counters_.corrupt_frames;
    ++health_.errors;
    return false;
  }
  if (is_jpeg) {
    if (const std::string problem = mjpeg_frame_problem(frame.bytes.data(), frame.bytes.size()); !problem.empty()) {
      std::lock_guard lock(mutex_);
      ++counters_.corrupt_frames;
      ++health_.errors;
      return false;
    }
    try {
      // A damaged header may claim any size: never allocate for one the stream cannot have.
      const JpegHeader h = decoder_.header(frame.bytes.data(), frame.bytes.size());
      if (h.width != settings_.frame_size.width || h.height != settings_.frame_size.height) {
        throw DecodeError("a " + std::to_string(h.width) + "x" + std::to_string(h.height) + " frame");
      }
      decoder_.decode_into(frame.bytes.data(), frame.bytes.size(), scale, image);
    } catch (const DecodeError&) {
      std::lock_guard lock(mutex_);
      ++counters_.corrupt_frames;
      ++health_.errors;
      return false;
    }
  } else {
    // YUYV: 2 bytes a pixel, rows of the driver's bytes_per_line (padding allowed).
    const int w = settings_.frame_size.width, h = settings_.frame_size.height;
    const size_t pitch = std::max<size_t>(size_t(w) * 2, size_t(std::max(0, format.bytes_per_line)));
    if (frame.bytes.size() < pitch * (h - 1) + size_t(w) * 2) {
      std::lock_guard lock(mutex_);
      ++counters_.corrupt_frames;
      ++health_.errors;
      return false;
    }
    const cv::Mat yuyv(h, w, CV_8UC2, const_cast<uint8_t*>(frame.bytes.data()), pitch);
    cv::cvtColor(yuyv, image, cv::COLOR_YUV2BGR_YUYV);
    scale = 1;
  }
  const cv::Size expected((settings_.frame_size.width + scale - 1) / scale, (settings_.frame_size.height + scale - 1) / scale);
  if (image.size() != expected) {
    std::lock_guard lock(mutex_);
    ++counters_.corrupt_frames;
    ++health_.errors;
    health_.message = "a frame of " + std::to_string(image.cols * scale) + "x" + std::to_string(image.rows * scale) +
                      " in a " + std::to_string(settings_.frame_size.width) + "x" +
                      std::to_string(settings_.frame_size.height) + " stream: skipped";
    return false;
  }
  const auto rig = rig_for_scale(scale);
  if (check_lens) {
    std::vector<LensCircleReport> reports;
    std::string warning;
    for (const LensCrop& crop : settings_.crops) {
      const cv::Rect roi(crop.rect.x / scale, crop.rect.y / scale, crop.rect.width / scale, crop.rect.height / scale);
      reports.push_back(check_lens_circle(*settings_.calibration->find(crop.camera), image, roi, scale));
      if (reports.back().found && reports.back().offset_px > kLensOffsetWarnPx) {
        warning += (warning.empty() ? "" : "; ") + describe(reports.back());
      }
    }
    std::lock_guard lock(mutex_);
    counters_.lens_circles = std::move(reports);
    last_lens_check_ = Clock::now();
    if (!warning.empty()) {
      const std::string message = "calibration off: " + warning + " (see 'insta360-lens-check --fit')";
      // Into the log too, once per change: a headless robot's journal should show it.
      if (health_.message != message) std::cerr << "omniviewd: source '" << name() << "': " << message << std::endl;
      health_.message = message;
    }
  }
  if (!any_wanted) return false;

  auto frames = std::make_shared<FrameSet>();
  frames->arrival = frame.dequeued;
  frames->capture_time = clock_.to_system(frame.monotonic_time, frame.dequeued);
  frames->rig = rig;
  frames->images.assign(rig->cameras().size(), image);  // one decoded frame, shared by every lens
  if (is_jpeg && scale == 1) {
    // A recording keeps the camera's own JPEG (each lens camera is the whole frame).
    EncodedImage encoded{"jpeg", std::make_shared<const std::vector<uint8_t>>(frame.bytes)};
    frames->encoded.assign(rig->cameras().size(), encoded);
  }
  {
    std::lock_guard lock(mutex_);
    if (rig != current_rig_) {
      current_rig_ = rig;
      ++rig_version_;
      counters_.decode_scale = scale;
    }
    frames->rig_version = rig_version_;
    frames->sequence = ++sequence_;
    counters_.clock_fallbacks = clock_.fallbacks();
  }
  on_frame(std::move(frames));
  std::lock_guard lock(mutex_);
  ++health_.frames;
  return true;
}

}  // namespace omniview::insta360
