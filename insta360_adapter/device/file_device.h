// A recording played as if it were the camera: the `file:` form of the `insta360` and
// `v4l2` sources (demos, CI, a recording taken on the robot). Everything after the device
// (decode, split, the rig, faults) is the same code a live camera goes through.
//
//   - a folder of JPEG frames with `timestamps.txt` ("SECONDS FILE" per line), or without
//     it every *.jpg in name order at `rate_hz`;
//   - an MJPEG file (JPEGs back to back, e.g. `ffmpeg -f v4l2 -input_format mjpeg -i
//     /dev/video2 -c:v copy air.mjpeg`) with `air.mjpeg.timestamps` ("SECONDS" per line)
//     beside it, or at `rate_hz`.
// Frames are played at their recorded spacing (times `speed`), looping if asked.
#pragma once

#include <memory>
#include <string>

#include "insta360_adapter/device/video_device.h"

namespace omniview::insta360 {

struct FilePlayback {
  double rate_hz = 30;  // when the recording has no timestamps
  double speed = 1;
  bool loop = true;
};

// Loads the recording's frames (compressed, into memory) and their times. Throws
// std::runtime_error naming the file for a missing or empty recording or bad timestamps.
std::unique_ptr<VideoDevice> open_file_device(const std::string& path, const FilePlayback& playback);

}  // namespace omniview::insta360
