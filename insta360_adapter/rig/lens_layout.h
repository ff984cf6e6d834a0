// Where each lens' image lies in the device's frame, and the daemon's rig for a frame.
//
// An Insta360 Air sends one 2:1 MJPEG frame holding both fisheye images side by side.
// Its calibration (ours, or a kalibr camchain of the split images) is in lens-image
// pixels. Instead of copying each half into its own image, every lens camera of the
// daemon's rig is the *whole* frame with its principal point moved by the lens' crop
// origin and a mask of its crop rectangle: both cameras share one decoded frame, packed
// as the maps read it, and no pixel is copied. At 1/2 or 1/4 DCT scaling the intrinsics
// scale with it.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core/types.hpp>

#include "core/rig/rig.h"

namespace omniview::insta360 {

struct LensCrop {
  std::string camera;  // the calibration's camera
  cv::Rect rect;       // in full-resolution frame pixels; its size is the calibrated size
};

// Default crops: the calibration's cameras side by side from the left, each its own
// calibrated width (an Air: [front | back] in a 3008 x 1504 frame; a plain camera: the
// whole frame).
std::vector<LensCrop> side_by_side(const Rig& calibration);

// Checks that every crop names a calibration camera, has its calibrated size and lies in
// the `frame`; throws std::invalid_argument saying which does not.
void check_crops(const Rig& calibration, const std::vector<LensCrop>& crops, cv::Size frame);

// The rig the daemon serves for frames of `frame` size decoded at 1/scale: the
// calibration's frames, and one camera per crop as described above.
Rig frame_rig(const Rig& calibration, const std::vector<LensCrop>& crops, cv::Size frame, int scale);

// `model` with its principal point moved by `offset` (pixels) and then the image scaled
// by 1/scale (pixel centres at integers: c' = (c + 0.5) / scale - 0.5).
CameraModel shift_and_scale(const CameraModel& model, cv::Point2d offset, int scale);

}  // namespace omniview::insta360
