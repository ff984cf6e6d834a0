// Internals of the map builder shared by its exact and adaptive row builders: per-camera
// constants and the vectorisable kernels. Not part of the public API.
#pragma once

#include <cstddef>
#include <cmath>
#include <cstdint>
#include <limits>
#include <variant>
#include <vector>

#include "core/camera/centre_score.h"
#include "core/map/fusion_map.h"

namespace omniview::map_internal {

inline constexpr float kInvalid = std::numeric_limits<float>::infinity();

// Where a camera's samples may lie, for encoding them.
struct SampleLimits {
  float max_u = 0, max_v = 0;    // last pixel centre
  float max_x0 = 0, max_y0 = 0;  // last column/row a bilinear footprint may start at
  int width_px = 0;
};

// Everything the per-row loops need about one camera, precomputed in float.
struct CameraSetup {
  const Camera* camera = nullptr;
  float R[9], t[3];        // T_cam_view
  bool limit_fov = false;  // camera.fov_deg set
  bool wide_fov = false;   // fov_deg > 180
  float cos_half_fov = -1, cos2_half_fov = 1;
  float max_u = 0, max_v = 0;  // last pixel centre
  SampleLimits limits;
  CentreScore centre;  // the fusion criterion (core/camera/centre_score.h)
  cv::Mat feather;  // blend only: CV_32F weight in [0, 1] per camera pixel
  // Blend only: the camera's centre in the view frame (for parallax), and how fast its
  // weight falls with distance from the image centre (see build_rows_exact).
  float centre_view[3] = {0, 0, 0};
  float centre_falloff = 0;  // per unit of sqrt(score)
};

// Blend seams: doubled lines come from blending two cameras that disagree. Where the two
// copies of an object off the surface would lie more than this many view pixels apart,
// the blend band narrows in proportion (a cut of a few pixels reads better than a ghost).
inline constexpr float kGhostTolerancePx = 2;
inline constexpr float kMaxBandNarrowing = 32;

struct RowScratch {
  explicit RowScratch(int w) : x(w), y(w), z(w), u(w), v(w), score(w), valid(w) {}
  std::vector<float> x, y, z, u, v, score;
  std::vector<uint8_t> valid;
};

// Projects one row of surface points into one camera. Written without branches so GCC
// vectorises it once `project` is inlined for the concrete model. score is the paper's
// fusion criterion (CentreScore, shared with the cloud colourer); kInvalid where the camera
// cannot see.
template <typename Model>
[[gnu::always_inline]] inline void project_row(const Model& model, const CameraSetup& c, int n, const float* __restrict x,
                 const float* __restrict y, const float* __restrict z, const uint8_t* __restrict valid,
                 float* __restrict out_u, float* __restrict out_v, float* __restrict score) {
  const CentreScore centre = c.centre;  // a local: GCC keeps it in registers and vectorises the loop
  for (int i = 0; i < n; ++i) {
    const float xc = c.R[0] * x[i] + c.R[1] * y[i] + c.R[2] * z[i] + c.t[0];
    const float yc = c.R[3] * x[i] + c.R[4] * y[i] + c.R[5] * z[i] + c.t[1];
    const float zc = c.R[6] * x[i] + c.R[7] * y[i] + c.R[8] * z[i] + c.t[2];
    float u, v;
    bool ok = model.project(xc, yc, zc, u, v);
    // Inside the lens' cone: zc >= cos(fov/2) |p|, compared squared to avoid a sqrt.
    const float z2 = zc * zc, cos2_norm2 = c.cos2_half_fov * (xc * xc + yc * yc + z2);
    const bool in_narrow_cone = (zc >= 0.0f) & (z2 >= cos2_norm2);  // fov <= 180
    const bool in_wide_cone = (zc >= 0.0f) | (z2 <= cos2_norm2);    // fov > 180
    const bool in_cone = (c.wide_fov & in_wide_cone) | (!c.wide_fov & in_narrow_cone);
    ok = ok & (valid[i] != 0) & (!c.limit_fov | in_cone);
    ok = ok & (u >= 0.0f) & (v >= 0.0f) & (u <= c.max_u) & (v <= c.max_v);
    out_u[i] = u;
    out_v[i] = v;
    score[i] = ok ? centre(u, v) : kInvalid;
  }
}

// project_row for the camera's concrete model, inlined into the caller. Not std::visit,
// nor a lambda: both leave out-of-line functions compiled for the baseline target only,
// so inside an OMNIVIEW_MULTIVERSION caller the projection never got AVX2.
template <size_t I = 0>
[[gnu::always_inline]] inline void project_camera_row(const CameraSetup& c, int n, const float* __restrict x,
                                                      const float* __restrict y, const float* __restrict z,
                                                      const uint8_t* __restrict valid, float* __restrict out_u,
                                                      float* __restrict out_v, float* __restrict score) {
  if constexpr (I < std::variant_size_v<CameraModel>) {
    if (c.camera->model.index() == I) {
      project_row(*std::get_if<I>(&c.camera->model), c, n, x, y, z, valid, out_u, out_v, score);
    } else {
      project_camera_row<I + 1>(c, n, x, y, z, valid, out_u, out_v, score);
    }
  }
}

// A MapEntry's second word: fx, fy and cam in its low three bytes.
inline uint32_t pack_rest(uint32_t fx, uint32_t fy, uint32_t cam) { return fx | (fy << 8) | (cam << 16); }
inline const uint32_t kNoRest = pack_rest(0, 0, kNoCamera);

inline MapEntry make_entry(uint32_t offset, uint32_t rest) {
  MapEntry e = kBlackEntry;
  e.offset = offset;
  e.fx = static_cast<uint8_t>(rest);
  e.fy = static_cast<uint8_t>(rest >> 8);
  e.cam = static_cast<uint8_t>(rest >> 16);
  return e;
}

// Encodes a sample position: the 2x2 footprint stays inside the image, fractions in
// 1/256 px. Returns the offset; `rest` receives fx, fy, cam.
inline uint32_t encode(const SampleLimits& c, float u, float v, uint32_t cam, uint32_t& rest) {
  // Clamp first: converting an out-of-range float to int is undefined.
  // (Plain ternaries: std::min/max on references keep GCC from vectorising.)
  float uc = u > 0.0f ? u : 0.0f, vc = v > 0.0f ? v : 0.0f;
  uc = uc < c.max_u ? uc : c.max_u;
  vc = vc < c.max_v ? vc : c.max_v;
  // The footprint's top-left pixel; one left/up at the last column/row.
  const float x0 = static_cast<float>(static_cast<int>(uc < c.max_x0 ? uc : c.max_x0));
  const float y0 = static_cast<float>(static_cast<int>(vc < c.max_y0 ? vc : c.max_y0));
  const float fx = (uc - x0) * 256.0f + 0.5f, fy = (vc - y0) * 256.0f + 0.5f;
  // float -> int32 -> uint32: SSE2 converts only to signed integers.
  rest = pack_rest(static_cast<uint32_t>(static_cast<int>(fx < 255.0f ? fx : 255.0f)),
                   static_cast<uint32_t>(static_cast<int>(fy < 255.0f ? fy : 255.0f)), cam);
  return static_cast<uint32_t>(static_cast<int>(y0) * c.width_px + static_cast<int>(x0));
}

// Keeps, per pixel, the candidate with the lowest score: the paper's rule. All 32-bit
// lanes and selects, so it vectorises.
[[gnu::always_inline]] inline void select_nearest(const CameraSetup& c, uint32_t cam, int n, const float* __restrict u,
                    const float* __restrict v, const float* __restrict score, float* __restrict best,
                    uint32_t* __restrict offset, uint32_t* __restrict rest) {
  for (int i = 0; i < n; ++i) {
    uint32_t candidate_rest;
    const uint32_t candidate = encode(c.limits, u[i], v[i], cam, candidate_rest);
    // Strict: ties go to the lower camera index. Masks rather than ?: keep GCC's
    // if-conversion out of it, which otherwise leaves this loop scalar.
    const uint32_t take = 0u - static_cast<uint32_t>(score[i] < best[i]);
    best[i] = score[i] < best[i] ? score[i] : best[i];
    offset[i] = (candidate & take) | (offset[i] & ~take);
    rest[i] = (candidate_rest & take) | (rest[i] & ~take);
  }
}

inline bool mask_allows(const Camera& c, float u, float v) {
  if (c.mask.empty()) return true;
  return c.mask.at<uint8_t>(static_cast<int>(v + 0.5f), static_cast<int>(u + 0.5f)) > 127;
}

// Rows [row_begin, row_end) computed exactly, pixel by pixel (and the blend policy); with
// `occlusion`, a camera competes only for the points it sees unhidden.
void build_rows_exact(const View& view, const std::vector<CameraSetup>& setups, bool blend, FusionMap& map,
                      int row_begin, int row_end, const Occlusion* occlusion = nullptr);

// Marks score[i] invalid where `occluder` hides row point i from camera c (occlusion.h).
// `judged`: the row's entries of Occlusion::judged, or null for all.
inline void drop_hidden(const CameraSetup& c, const CameraOccluder& occluder, const Occlusion& rule, int n,
                        const uint8_t* judged, const float* x, const float* y, const float* z, const float* u,
                        const float* v, float* score) {
  for (int i = 0; i < n; ++i) {
    if (score[i] == kInvalid || (judged && !judged[i])) continue;
    const float xc = c.R[0] * x[i] + c.R[1] * y[i] + c.R[2] * z[i] + c.t[0];
    const float yc = c.R[3] * x[i] + c.R[4] * y[i] + c.R[5] * z[i] + c.t[1];
    const float zc = c.R[6] * x[i] + c.R[7] * y[i] + c.R[8] * z[i] + c.t[2];
    const float range = std::sqrt(xc * xc + yc * yc + zc * zc);
    if (hidden_behind(range, occluder.at(u[i], v[i]), rule.tolerance_rel, rule.tolerance_m)) score[i] = kInvalid;
  }
}

// The adaptive builder's block size (adaptive/bands.h).
inline constexpr int kBlock = 8;

}  // namespace omniview::map_internal
