// A capture device through the kernel's V4L2 API: ioctls on the device node, mmap'd
// streaming buffers, the driver's monotonic timestamps. No libv4l2 or OpenCV in between,
// so formats, timestamps and errors reach us as the kernel reports them.
#pragma once

#include <memory>
#include <string>

#include "insta360_adapter/device/video_device.h"

namespace omniview::insta360 {

// Opens `path` (/dev/videoN). Throws DeviceError: kNotFound, kPermission, kBusy (naming
// the processes that hold it, where /proc tells), kNotCapture.
std::unique_ptr<VideoDevice> open_v4l2_device(const std::string& path);

// "held by pid 1234 (ffmpeg)" for every other process with `path` open (those /proc lets
// us see); empty when none is found.
std::string device_holders(const std::string& path, const std::string& proc_root = "/proc");

}  // namespace omniview::insta360
