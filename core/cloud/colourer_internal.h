// What the colourer's files share: each camera's fixed set-up, one camera's projections of
// the current cloud and its depth buffer (camera_pass.cc), and pixel sampling.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

#include <Eigen/Core>

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

namespace cloud_internal {

// One camera's projections of the current cloud and its depth buffer.
struct CameraPass {
  bool active = false;
  std::vector<float> u, v, range;
  std::vector<uint8_t> valid;  // bit 1: the model images the point; bit 0: a usable pixel too
  float inv_cell = 1, offset = 0;
  int reach = 1;
  int rows = 0, cols = 0;  // depth buffer cells (the image and `reach` cells past it)
  // Nearest range per cell, one buffer per point range (splatted in parallel, then merged
  // into the first). Each has `reach` far cells more on every side, so the covering depth
  // needs no bounds checks, and one cell more at the end that takes what falls outside.
  std::vector<std::vector<float>> depth;
  std::vector<float> occluder;  // rows x cols: the depth of a surface covering each cell
  int padded_cols() const { return cols + 2 * reach; }
  size_t padded_size() const { return size_t(rows + 2 * reach) * size_t(padded_cols()) + 1; }
};

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

// One camera's projections of points [0, n): pixel (u, v), range, and the `valid` bits above
// (bit 0 for any pixel inside the image; the usable region is applied by the caller).
void project_camera(const CameraModel& model, const Eigen::Matrix<float, 3, 4>& T_cam_cloud, const float* x,
                    const float* y, const float* z, size_t n, float max_u, float max_v, float* u, float* v,
                    float* range, uint8_t* valid);

// Splats points [0, n) of `pass` (already offset by the caller) into `depth`, one of its
// padded buffers: nearest range per cell.
void splat(const CameraPass& pass, const float* u, const float* v, const float* range,
           const uint8_t* valid, size_t n, float* depth);

// pass.occluder from pass.depth[0] (see occluding_depth in camera_pass.cc).
void occluding_depth(CameraPass& pass);

inline uint8_t to_byte(float v) { return static_cast<uint8_t>(std::clamp(v + 0.5f, 0.f, 255.f)); }

}  // namespace cloud_internal
}  // namespace omniview
