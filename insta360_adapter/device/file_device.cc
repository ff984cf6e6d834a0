#include "insta360_adapter/device/file_device.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <thread>

#include "insta360_adapter/decode/jpeg_decoder.h"
#include "insta360_adapter/decode/mjpeg_stream.h"

namespace omniview::insta360 {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw std::runtime_error(p.string() + ": cannot read");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class FileDevice : public VideoDevice {
 public:
  FileDevice(std::string path, const FilePlayback& playback) : path_(std::move(path)), playback_(playback) {
    std::vector<TimedEntry> times;
    if (fs::is_directory(path_)) {
      const fs::path index = fs::path(path_) / "timestamps.txt";
      if (fs::exists(index)) {
        times = parse_timestamps(read_file(index), index.string());
        for (auto& t : times) {
          if (t.file.empty()) throw std::runtime_error(index.string() + ": every line needs 'SECONDS FILE'");
          frames_.push_back(to_bytes(read_file(fs::path(path_) / t.file)));
        }
      } else {
        std::vector<fs::path> files;
        for (const auto& e : fs::directory_iterator(path_)) {
          const std::string ext = e.path().extension().string();
          if (ext == ".jpg" || ext == ".jpeg" || ext == ".JPG") files.push_back(e.path());
        }
        std::sort(files.begin(), files.end());
        for (const auto& f : files) frames_.push_back(to_bytes(read_file(f)));
      }
    } else {
      const std::string data = read_file(path_);
      const auto* bytes = reinterpret_cast<const uint8_t*>(data.data());
      for (const auto& [offset, size] : split_mjpeg(bytes, data.size())) {
        frames_.emplace_back(bytes + offset, bytes + offset + size);
      }
      const fs::path index = path_ + ".timestamps";
      if (fs::exists(index)) times = parse_timestamps(read_file(index), index.string());
    }
    if (frames_.empty()) throw std::runtime_error(path_ + ": no JPEG frames in this recording");
    if (!times.empty() && times.size() != frames_.size()) {
      throw std::runtime_error(path_ + ": " + std::to_string(frames_.size()) + " frames but " +
                               std::to_string(times.size()) + " timestamps");
    }
    for (size_t i = 0; i < frames_.size(); ++i) {
      const double t = times.empty() ? double(i) / playback_.rate_hz : times[i].seconds - times[0].seconds;
      offsets_.push_back(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t / playback_.speed)));
    }
    // A loop lasts one frame spacing longer than its last frame.
    const auto spacing = frames_.size() > 1 ? (offsets_.back() - offsets_.front()) / int64_t(frames_.size() - 1)
                                            : std::chrono::duration_cast<Clock::duration>(
                                                  std::chrono::duration<double>(1 / (playback_.rate_hz * playback_.speed)));
    loop_length_ = offsets_.back() + spacing;
    JpegDecoder decoder;
    const JpegHeader h = decoder.header(frames_[0].data(), frames_[0].size());
    width_ = h.width;
    height_ = h.height;
  }

  std::string name() const override { return path_ + " (recording)"; }

  std::vector<FormatOption> formats() override {
    return {{kMjpeg, width_, height_, {std::chrono::duration<double>(loop_length_).count() > 0
                                           ? double(frames_.size()) / std::chrono::duration<double>(loop_length_).count()
                                           : 0}}};
  }

  CaptureFormat start(const CaptureFormat& wanted) override {
    if (wanted.pixel_format != kMjpeg || wanted.width != width_ || wanted.height != height_) {
      throw DeviceError(DeviceFault::kNoFormat, name() + " holds MJPG " + std::to_string(width_) + "x" +
                                                    std::to_string(height_) + " frames");
    }
    start_ = Clock::now();
    next_ = 0;
    return {kMjpeg, width_, height_, wanted.fps, 0};
  }

  bool next_frame(std::chrono::milliseconds timeout, CapturedFrame& frame) override {
    if (!playback_.loop && next_ >= frames_.size()) {
      std::this_thread::sleep_for(timeout);  // played once: a stream that ended
      return false;
    }
    const size_t index = next_ % frames_.size();
    const auto due = start_ + loop_length_ * int64_t(next_ / frames_.size()) + offsets_[index];
    const auto now = Clock::now();
    if (due > now + timeout) {
      std::this_thread::sleep_for(timeout);
      return false;
    }
    std::this_thread::sleep_until(due);
    // Behind (a slow machine): skip ahead rather than replay old frames in a burst.
    if (Clock::now() - due > loop_length_) start_ = Clock::now() - offsets_[index] - loop_length_ * int64_t(next_ / frames_.size());
    frame.bytes = frames_[index];
    frame.sequence = next_++;
    frame.dequeued = Clock::now();
    frame.monotonic_time = std::chrono::duration_cast<std::chrono::nanoseconds>(due.time_since_epoch());
    return true;
  }

 private:
  static std::vector<uint8_t> to_bytes(const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); }

  std::string path_;
  FilePlayback playback_;
  std::vector<std::vector<uint8_t>> frames_;
  std::vector<Clock::duration> offsets_;
  Clock::duration loop_length_{};
  int width_ = 0, height_ = 0;
  Clock::time_point start_;
  uint64_t next_ = 0;
};

}  // namespace

std::unique_ptr<VideoDevice> open_file_device(const std::string& path, const FilePlayback& playback) {
  if (!fs::exists(path)) throw std::runtime_error(path + ": no such recording (a folder of JPEGs or an MJPEG file)");
  return std::make_unique<FileDevice>(path, playback);
}

}  // namespace omniview::insta360
