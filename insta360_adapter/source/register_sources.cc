#include "insta360_adapter/source/register_sources.h"

#include <mutex>

#include "insta360_adapter/source/capture_config.h"
#include "server/source/source_registry.h"

namespace omniview::insta360 {

void register_insta360_sources() {
  static std::once_flag once;
  std::call_once(once, [] {
    register_source_type("insta360",
                         "an Insta360 Air (dual 210 deg fisheye on USB/UVC) as two cameras of one rig, or its "
                         "recording (keys: device | file, calibration, rig_frame, mount, format, lenses, "
                         "decode_scale, lens_check, rate_hz, speed, loop)",
                         make_insta360_source);
    register_source_type("v4l2",
                         "any V4L2/UVC camera (MJPEG or YUYV) with a kalibr calibration, or its recording (keys: "
                         "device | file, calibration, frame, rig_frame, mount, format, lenses, decode_scale)",
                         make_v4l2_source);
  });
}

}  // namespace omniview::insta360
