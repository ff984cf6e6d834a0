// What colourer.cc and nearest_centre.cc share: each camera's fixed set-up, one camera's
// projections of the current cloud, and pixel sampling.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/cloud/colourer.h"

namespace omniview {

struct CloudColourer::CameraSetup {
  cv::Mat usable;   // CV_8UC1, 255 where the camera's image, mask and lens allow a pixel
  cv::Mat feather;  // CV_32F blend weights, made on first use for `feather_px`
  double feather_px = -1;
  float cell_px = 1;  // depth buffer cell
  double px_per_rad = 1;
  float cx = 0, cy = 0, inv_half_diag2 = 1;
  bool all_usable = false;  // no mask, no lens limit: every pixel of the image may colour
};

// One camera's projections of the current cloud and its depth buffer.
struct CloudColourer::CameraPass {
  bool active = false;
  std::vector<float> u, v, range;
  std::vector<uint8_t> valid;  // bit 1: the model images the point; bit 0: a usable pixel too
  float inv_cell = 1, offset = 0;
  cv::Mat depth, up, down, left, right, occluder;
};

namespace cloud_internal {

// Bilinear sample at (u, v) inside [0, W-1] x [0, H-1]; R, G, B out.
[[gnu::always_inline]] inline void sample(const cv::Mat& image, float u, float v, float rgb[3]) {
  const int x0 = static_cast<int>(u), y0 = static_cast<int>(v);
  const int x1 = std::min(x0 + 1, image.cols - 1), y1 = std::min(y0 + 1, image.rows - 1);
  const float ax = u - x0, ay = v - y0;
  const float w00 = (1 - ax) * (1 - ay), w01 = ax * (1 - ay), w10 = (1 - ax) * ay, w11 = ax * ay;
  if (image.type() == CV_8UC1) {
    const uint8_t* r0 = image.ptr<uint8_t>(y0);
    const uint8_t* r1 = image.ptr<uint8_t>(y1);
    const float g = w00 * r0[x0] + w01 * r0[x1] + w10 * r1[x0] + w11 * r1[x1];
    rgb[0] = rgb[1] = rgb[2] = g;
    return;
  }
  const cv::Vec3b* r0 = image.ptr<cv::Vec3b>(y0);
  const cv::Vec3b* r1 = image.ptr<cv::Vec3b>(y1);
  for (int k = 0; k < 3; ++k) {  // BGR in, RGB out
    rgb[2 - k] = w00 * r0[x0][k] + w01 * r0[x1][k] + w10 * r1[x0][k] + w11 * r1[x1][k];
  }
}

inline uint8_t to_byte(float v) { return static_cast<uint8_t>(std::clamp(v + 0.5f, 0.f, 255.f)); }

}  // namespace cloud_internal
}  // namespace omniview
