// What the colourer's files share: each camera's fixed set-up, one camera's projections of
// the current cloud and its depth buffer (camera_pass.cc), and pixel sampling.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <opencv2/core/mat.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <Eigen/Core>

#include "core/camera/camera.h"
#include "core/camera/centre_score.h"
#include "core/cloud/colourer.h"

namespace omniview {

struct CloudColourer::CameraSetup {
  cv::Mat usable;   // CV_8UC1, 255 where the camera's image, mask and lens allow a pixel
  cv::Mat feather;  // CV_32F blend weights, made on first use for `feather_px`
  double feather_px = -1;
  float cell_px = 1;  // depth buffer cell
  double px_per_rad = 1;
  CentreScore centre;  // the fusion criterion, the same as the views' (core/camera/centre_score.h)
  bool all_usable = false;  // no mask, no lens limit: every pixel of the image may colour
};

namespace cloud_internal {

// The points of one range that a camera sees on a usable pixel of its image, in point
// order: what fusion reads. Kept apart from the points the camera does not see (most of
// them: five cameras share a lidar's circle), which only the depth buffer needs.
struct alignas(64) Seen {  // a cache line of its own: threads fill neighbouring ones
  std::unique_ptr<uint32_t[]> index;
  std::unique_ptr<float[]> u, v, range;
  size_t size = 0, capacity = 0;
  // Room for n points; the arrays are left uninitialised (the pass writes what it keeps).
  void reserve(size_t n) {
    if (n <= capacity) return;
    index.reset(new uint32_t[n]);
    u.reset(new float[n]);
    v.reset(new float[n]);
    range.reset(new float[n]);
    capacity = n;
  }
  // The entries of points [begin, end).
  std::pair<size_t, size_t> span(size_t begin, size_t end) const {
    const uint32_t* first = index.get();
    return {size_t(std::lower_bound(first, first + size, begin) - first),
            size_t(std::lower_bound(first, first + size, end) - first)};
  }
};

// One camera's view of the current cloud: the points it sees, and its depth buffer.
struct CameraPass {
  bool active = false;
  std::vector<Seen> seen;  // one per point range, in order
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
  // The covering depth at pixel (u, v) of the image.
  float occluder_at(float u, float v) const {
    return occluder[size_t(static_cast<int>(v * inv_cell + offset)) * cols + static_cast<int>(u * inv_cell + offset)];
  }
};

// Pixels per radian near the camera's image centre, from two neighbouring rays (the depth
// buffer's cell size in pixels is this times the cell's angle).
double pixels_per_radian(const Camera& camera);

// Sizes `pass`'s depth buffer for `camera`: cells of `cell_deg` (at least a pixel), reaching
// `reach` cells past the image on every side, so that a surface just outside the picture
// still covers what lies behind it at the picture's edge.
void size_depth_buffer(CameraPass& pass, const Camera& camera, double px_per_rad, double cell_deg, int reach);

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
#if defined(__SSE2__)
  // The three channels in the lanes of one register: the same products and sums, in the
  // same order, as the loop below, a quarter of the conversions.
  const auto lanes = [](const cv::Vec3b& p) {
    const __m128i bytes = _mm_cvtsi32_si128(p[0] | (p[1] << 8) | (p[2] << 16));
    const __m128i zero = _mm_setzero_si128();
    return _mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpacklo_epi8(bytes, zero), zero));
  };
  const __m128 sum = _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(w00), lanes(r0[x0])),
                                                      _mm_mul_ps(_mm_set1_ps(w01), lanes(r0[x1]))),
                                           _mm_mul_ps(_mm_set1_ps(w10), lanes(r1[x0]))),
                                _mm_mul_ps(_mm_set1_ps(w11), lanes(r1[x1])));
  alignas(16) float bgr[4];
  _mm_store_ps(bgr, sum);
  rgb[0] = bgr[2];  // BGR in, RGB out
  rgb[1] = bgr[1];
  rgb[2] = bgr[0];
#else
  for (int k = 0; k < 3; ++k) {  // BGR in, RGB out
    rgb[2 - k] = w00 * r0[x0][k] + w01 * r0[x1][k] + w10 * r1[x0][k] + w11 * r1[x1][k];
  }
#endif
}

// One camera's projections of points [0, n): pixel (u, v), range, and the `valid` bits above
// (bit 0 for any pixel inside the image; the usable region is applied by the caller).
void project_camera(const CameraModel& model, const Eigen::Matrix<float, 3, 4>& T_cam_cloud, const float* x,
                    const float* y, const float* z, size_t n, float max_u, float max_v, float* u, float* v,
                    float* range, uint8_t* valid);

// Points first .. first + n - 1, projected: splats those the model images into `depth` (one
// of the pass's padded buffers; null without occlusion), nearest range per cell, and keeps
// those on a usable pixel in `seen`.
void splat_and_keep(const CameraPass& pass, size_t first, const float* u, const float* v, const float* range,
                    const uint8_t* valid, size_t n, float* depth, Seen& seen);

// pass.occluder from pass.depth[0] (see occluding_depth in camera_pass.cc).
void occluding_depth(CameraPass& pass);

inline uint8_t to_byte(float v) { return static_cast<uint8_t>(std::clamp(v + 0.5f, 0.f, 255.f)); }

}  // namespace cloud_internal
}  // namespace omniview
