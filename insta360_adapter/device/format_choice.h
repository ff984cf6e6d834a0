// Which of the formats a device offers to capture with.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "insta360_adapter/device/video_device.h"

namespace omniview::insta360 {

struct FormatRequest {
  std::vector<uint32_t> pixel_formats = {kMjpeg};  // acceptable, in order of preference
  int width = 0, height = 0;                       // 0: the largest offered
  double fps = 0;                                  // 0: the highest offered at that size
  double aspect = 0;                               // > 0: only sizes of this width/height (2 for dual fisheye)
};

// The largest matching size (then the preferred format, then the requested or highest
// rate). Throws DeviceError(kNoFormat) naming `device` and listing every offer when
// nothing matches.
CaptureFormat choose_format(const std::vector<FormatOption>& offers, const FormatRequest& request,
                            const std::string& device);

}  // namespace omniview::insta360
