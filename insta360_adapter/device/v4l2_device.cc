#include "insta360_adapter/device/v4l2_device.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace omniview::insta360 {
namespace {

int xioctl(int fd, unsigned long request, void* arg) {
  int r;
  do {
    r = ::ioctl(fd, request, arg);
  } while (r == -1 && errno == EINTR);
  return r;
}

DeviceFault fault_of(int err) {
  switch (err) {
    case ENOENT:
    case ENXIO:
      return DeviceFault::kNotFound;
    case ENODEV:
      return DeviceFault::kDisconnected;
    case EBUSY:
      return DeviceFault::kBusy;
    case EACCES:
    case EPERM:
      return DeviceFault::kPermission;
    default:
      return DeviceFault::kIo;
  }
}

class V4l2Device : public VideoDevice {
 public:
  V4l2Device(std::string path, int fd, std::string card) : path_(std::move(path)), fd_(fd), card_(std::move(card)) {}
  ~V4l2Device() override {
    if (streaming_) {
      int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      xioctl(fd_, VIDIOC_STREAMOFF, &type);
    }
    for (const auto& b : buffers_) ::munmap(b.start, b.length);
    ::close(fd_);
  }

  std::string name() const override { return path_ + " (" + card_ + ")"; }

  std::vector<FormatOption> formats() override {
    std::vector<FormatOption> out;
    for (uint32_t i = 0;; ++i) {
      v4l2_fmtdesc desc{};
      desc.index = i;
      desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      if (xioctl(fd_, VIDIOC_ENUM_FMT, &desc) != 0) break;
      for (uint32_t j = 0;; ++j) {
        v4l2_frmsizeenum size{};
        size.index = j;
        size.pixel_format = desc.pixelformat;
        if (xioctl(fd_, VIDIOC_ENUM_FRAMESIZES, &size) != 0) break;
        if (size.type != V4L2_FRMSIZE_TYPE_DISCRETE) {
          // Stepwise sizes (rare on UVC): offer the largest.
          out.push_back({desc.pixelformat, int(size.stepwise.max_width), int(size.stepwise.max_height), {}});
          break;
        }
        FormatOption option{desc.pixelformat, int(size.discrete.width), int(size.discrete.height), {}};
        for (uint32_t k = 0;; ++k) {
          v4l2_frmivalenum ival{};
          ival.index = k;
          ival.pixel_format = desc.pixelformat;
          ival.width = size.discrete.width;
          ival.height = size.discrete.height;
          if (xioctl(fd_, VIDIOC_ENUM_FRAMEINTERVALS, &ival) != 0 || ival.type != V4L2_FRMIVAL_TYPE_DISCRETE) break;
          if (ival.discrete.numerator > 0) option.fps.push_back(double(ival.discrete.denominator) / ival.discrete.numerator);
        }
        out.push_back(std::move(option));
      }
    }
    return out;
  }

  CaptureFormat start(const CaptureFormat& wanted) override {
    v4l2_format fmt{};
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    fmt.fmt.pix.width = uint32_t(wanted.width);
    fmt.fmt.pix.height = uint32_t(wanted.height);
    fmt.fmt.pix.pixelformat = wanted.pixel_format;
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    if (xioctl(fd_, VIDIOC_S_FMT, &fmt) != 0) fail("set format " + describe_format(wanted));
    CaptureFormat got{fmt.fmt.pix.pixelformat, int(fmt.fmt.pix.width), int(fmt.fmt.pix.height), wanted.fps,
                      int(fmt.fmt.pix.bytesperline)};
    if (got.pixel_format != wanted.pixel_format || got.width != wanted.width || got.height != wanted.height) {
      throw DeviceError(DeviceFault::kNoFormat, name() + ": asked for " + describe_format(wanted) +
                                                    ", the driver chose " + describe_format(got));
    }
    if (wanted.fps > 0) {
      v4l2_streamparm parm{};
      parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      parm.parm.capture.timeperframe.numerator = 1000;
      parm.parm.capture.timeperframe.denominator = uint32_t(wanted.fps * 1000 + 0.5);
      if (xioctl(fd_, VIDIOC_S_PARM, &parm) == 0 && parm.parm.capture.timeperframe.numerator > 0) {
        got.fps = double(parm.parm.capture.timeperframe.denominator) / parm.parm.capture.timeperframe.numerator;
      }
    }
    // Four buffers: one with us, the rest for the driver to fill while we decode.
    v4l2_requestbuffers req{};
    req.count = 4;
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    if (xioctl(fd_, VIDIOC_REQBUFS, &req) != 0) fail("request buffers");
    if (req.count < 2) throw DeviceError(DeviceFault::kIo, name() + ": the driver gave " + std::to_string(req.count) + " buffer(s)");
    for (uint32_t i = 0; i < req.count; ++i) {
      v4l2_buffer buf{};
      buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      buf.memory = V4L2_MEMORY_MMAP;
      buf.index = i;
      if (xioctl(fd_, VIDIOC_QUERYBUF, &buf) != 0) fail("query buffer");
      void* p = ::mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, buf.m.offset);
      if (p == MAP_FAILED) fail("mmap buffer");
      buffers_.push_back({p, buf.length});
      if (xioctl(fd_, VIDIOC_QBUF, &buf) != 0) fail("queue buffer");
    }
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(fd_, VIDIOC_STREAMON, &type) != 0) fail("start streaming");
    streaming_ = true;
    return got;
  }

  bool next_frame(std::chrono::milliseconds timeout, CapturedFrame& frame) override {
    pollfd p{fd_, POLLIN, 0};
    const int n = ::poll(&p, 1, int(timeout.count()));
    if (n < 0 && errno != EINTR) fail("poll");
    if (n <= 0) return false;
    if (p.revents & (POLLERR | POLLHUP)) {
      // UVC reports an unplugged device as POLLERR; DQBUF then says ENODEV.
      if (::access(path_.c_str(), F_OK) != 0) throw DeviceError(DeviceFault::kDisconnected, name() + ": unplugged");
    }
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    if (xioctl(fd_, VIDIOC_DQBUF, &buf) != 0) {
      if (errno == EAGAIN) return false;
      fail("dequeue buffer");
    }
    frame.dequeued = std::chrono::steady_clock::now();
    frame.sequence = buf.sequence;
    const bool monotonic = (buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
    frame.monotonic_time = monotonic ? std::chrono::seconds(buf.timestamp.tv_sec) + std::chrono::microseconds(buf.timestamp.tv_usec)
                                     : std::chrono::nanoseconds(0);
    const bool bad = (buf.flags & V4L2_BUF_FLAG_ERROR) != 0 || buf.index >= buffers_.size();
    if (!bad) {
      const auto* start = static_cast<const uint8_t*>(buffers_[buf.index].start);
      frame.bytes.assign(start, start + std::min<size_t>(buf.bytesused, buffers_[buf.index].length));
    } else {
      frame.bytes.clear();  // the driver flagged it corrupt: the caller counts it
    }
    // Back to the driver at once: the compressed bytes are ours now, decoding does not
    // hold a buffer the camera could be filling.
    if (xioctl(fd_, VIDIOC_QBUF, &buf) != 0) fail("re-queue buffer");
    return true;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    const int err = errno;
    std::string message = name() + ": " + what + ": " + std::strerror(err);
    if (err == EBUSY) {
      const std::string holders = device_holders(path_);
      message += holders.empty() ? " (another program is using it)" : " (" + holders + ")";
    }
    if (err == ENODEV) message = name() + ": unplugged (" + what + ")";
    throw DeviceError(fault_of(err), message);
  }
  static std::string describe_format(const CaptureFormat& f) {
    return fourcc_text(f.pixel_format) + " " + std::to_string(f.width) + "x" + std::to_string(f.height);
  }

  struct Buffer {
    void* start;
    size_t length;
  };
  std::string path_;
  int fd_;
  std::string card_;
  std::vector<Buffer> buffers_;
  bool streaming_ = false;
};

}  // namespace

std::string device_holders(const std::string& path, const std::string& proc_root) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path target = fs::weakly_canonical(path, ec);
  std::string out;
  const std::string self = std::to_string(::getpid());
  for (const auto& proc : fs::directory_iterator(proc_root, ec)) {
    const std::string pid = proc.path().filename().string();
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos || pid == self) continue;
    std::error_code fd_ec;
    for (const auto& fd : fs::directory_iterator(proc.path() / "fd", fd_ec)) {
      std::error_code link_ec;
      const fs::path link = fs::read_symlink(fd.path(), link_ec);
      if (link_ec || link != target) continue;
      std::string comm;
      std::getline(std::ifstream(proc.path() / "comm"), comm);
      out += (out.empty() ? "held by pid " : ", pid ") + pid + (comm.empty() ? "" : " (" + comm + ")");
      break;
    }
  }
  return out;
}

std::unique_ptr<VideoDevice> open_v4l2_device(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    std::string message = path + ": " + std::strerror(err);
    if (err == EACCES) message += " (add the daemon's user to the 'video' group)";
    if (err == ENOENT) message += " (not plugged in?)";
    throw DeviceError(fault_of(err), message);
  }
  v4l2_capability cap{};
  if (xioctl(fd, VIDIOC_QUERYCAP, &cap) != 0) {
    const int err = errno;
    ::close(fd);
    throw DeviceError(err == ENOTTY ? DeviceFault::kNotCapture : fault_of(err),
                      path + ": not a V4L2 device (" + std::strerror(err) + ")");
  }
  const uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  const std::string card(reinterpret_cast<const char*>(cap.card), strnlen(reinterpret_cast<const char*>(cap.card), sizeof cap.card));
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING)) {
    ::close(fd);
    throw DeviceError(DeviceFault::kNotCapture,
                      path + " (" + card + ") is not a streaming video capture node (UVC cameras also have a "
                                         "metadata node: use the other /dev/video of the pair)");
  }
  return std::make_unique<V4l2Device>(path, fd, card);
}

}  // namespace omniview::insta360
