#include "core/map/fusion_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/map/multiversion.h"
#include "core/map/usable_region.h"

namespace omniview {
namespace {

constexpr float kInvalid = std::numeric_limits<float>::infinity();

// Everything the per-row loops need about one camera, precomputed in float.
struct CameraSetup {
  const Camera* camera = nullptr;
  float R[9], t[3];        // T_cam_view
  bool limit_fov = false;  // camera.fov_deg set
  bool wide_fov = false;   // fov_deg > 180
  float cos_half_fov = -1, cos2_half_fov = 1;
  float max_u = 0, max_v = 0;  // last pixel centre
  float max_x0 = 0, max_y0 = 0;  // last column/row a bilinear footprint may start at
  int width_px = 0;
  float centre_u = 0, centre_v = 0, inv_w = 0, inv_h = 0;
  cv::Mat feather;  // blend only: CV_32F weight in [0, 1] per camera pixel
};

struct RowScratch {
  explicit RowScratch(int w) : x(w), y(w), z(w), u(w), v(w), score(w), valid(w) {}
  std::vector<float> x, y, z, u, v, score;
  std::vector<uint8_t> valid;
};

// Projects one row of surface points into one camera. Written without branches so GCC
// vectorises it once `project` is inlined for the concrete model. score is the paper's
// fusion criterion: squared distance from the image centre, normalised by image size so
// cameras of different resolution compete fairly; kInvalid where the camera cannot see.
template <typename Model>
[[gnu::always_inline]] inline void project_row(const Model& model, const CameraSetup& c, int n, const float* __restrict x,
                 const float* __restrict y, const float* __restrict z, const uint8_t* __restrict valid,
                 float* __restrict out_u, float* __restrict out_v, float* __restrict score) {
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
    const float du = (u - c.centre_u) * c.inv_w, dv = (v - c.centre_v) * c.inv_h;
    out_u[i] = u;
    out_v[i] = v;
    score[i] = ok ? du * du + dv * dv : kInvalid;
  }
}

// A MapEntry's second word: fx, fy and cam in its low three bytes.
inline uint32_t pack_rest(uint32_t fx, uint32_t fy, uint32_t cam) { return fx | (fy << 8) | (cam << 16); }
const uint32_t kNoRest = pack_rest(0, 0, kNoCamera);

MapEntry make_entry(uint32_t offset, uint32_t rest) {
  MapEntry e;
  e.offset = offset;
  e.fx = static_cast<uint8_t>(rest);
  e.fy = static_cast<uint8_t>(rest >> 8);
  e.cam = static_cast<uint8_t>(rest >> 16);
  return e;
}

// Encodes a sample position: the 2x2 footprint stays inside the image, fractions in
// 1/256 px. Returns the offset; `rest` receives fx, fy, cam.
inline uint32_t encode(const CameraSetup& c, float u, float v, uint32_t cam, uint32_t& rest) {
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
    const uint32_t candidate = encode(c, u[i], v[i], cam, candidate_rest);
    // Strict: ties go to the lower camera index. Masks rather than ?: keep GCC's
    // if-conversion out of it, which otherwise leaves this loop scalar.
    const uint32_t take = 0u - static_cast<uint32_t>(score[i] < best[i]);
    best[i] = score[i] < best[i] ? score[i] : best[i];
    offset[i] = (candidate & take) | (offset[i] & ~take);
    rest[i] = (candidate_rest & take) | (rest[i] & ~take);
  }
}

bool mask_allows(const Camera& c, float u, float v) {
  if (c.mask.empty()) return true;
  return c.mask.at<uint8_t>(static_cast<int>(v + 0.5f), static_cast<int>(u + 0.5f)) > 127;
}

CameraSetup make_setup(const Rig& rig, size_t index, const View& view, const Pose& T_frame_view,
                       const std::string& frame, bool blend, double feather_px) {
  const Camera& cam = rig.cameras()[index];
  CameraSetup s;
  s.camera = &cam;
  const Pose T_cam_view = rig.camera_pose(frame, index).inverse() * T_frame_view;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) s.R[3 * r + c] = static_cast<float>(T_cam_view.linear()(r, c));
    s.t[r] = static_cast<float>(T_cam_view.translation()(r));
  }
  s.limit_fov = cam.fov_deg > 0 && cam.fov_deg < 360;
  s.cos_half_fov = s.limit_fov ? static_cast<float>(std::cos(cam.fov_deg * M_PI / 360)) : -1.0f;
  s.cos2_half_fov = s.cos_half_fov * s.cos_half_fov;
  s.wide_fov = s.cos_half_fov < 0;
  s.max_u = static_cast<float>(cam.width - 1);
  s.max_v = static_cast<float>(cam.height - 1);
  s.max_x0 = static_cast<float>(cam.width - 2);
  s.max_y0 = static_cast<float>(cam.height - 2);
  s.width_px = cam.width;
  s.centre_u = s.max_u / 2;
  s.centre_v = s.max_v / 2;
  s.inv_w = 1.0f / static_cast<float>(cam.width);
  s.inv_h = 1.0f / static_cast<float>(cam.height);
  if (blend) s.feather = feather_weights(cam, feather_px);
  (void)view;
  return s;
}

// One band of output rows. Compiled twice on x86-64 (baseline SSE2 and x86-64-v3 with
// AVX2/FMA) and picked at run time, so robots with newer CPUs get 8-wide SIMD while the
// binary still runs everywhere; other architectures build it once.
OMNIVIEW_MULTIVERSION
void build_rows(const View& view, const std::vector<CameraSetup>& setups, bool blend, FusionMap& map, int row_begin,
                int row_end) {
  const int w = map.width;
  RowScratch s(w);
  std::vector<float> best(w), second(w);
  std::vector<uint32_t> offset(w), rest(w);
  for (int row = row_begin; row < row_end; ++row) {
    view.row_points(row, s.x.data(), s.y.data(), s.z.data(), s.valid.data());
    MapEntry* primary = &map.primary[static_cast<size_t>(row) * w];
    MapEntry* secondary = blend ? &map.secondary[static_cast<size_t>(row) * w] : nullptr;
    std::fill(best.begin(), best.end(), blend ? 0.0f : kInvalid);
    std::fill(second.begin(), second.end(), 0.0f);
    std::fill(rest.begin(), rest.end(), kNoRest);
    for (size_t ci = 0; ci < setups.size(); ++ci) {
      const CameraSetup& c = setups[ci];
      std::visit([&](const auto& model) {
        project_row(model, c, w, s.x.data(), s.y.data(), s.z.data(), s.valid.data(), s.u.data(), s.v.data(),
                    s.score.data());
      }, c.camera->model);
      if (!c.camera->mask.empty()) {
        for (int i = 0; i < w; ++i) {
          if (s.score[i] != kInvalid && !mask_allows(*c.camera, s.u[i], s.v[i])) s.score[i] = kInvalid;
        }
      }
      if (!blend) {
        select_nearest(c, static_cast<uint32_t>(ci), w, s.u.data(), s.v.data(), s.score.data(), best.data(),
                       offset.data(), rest.data());
        continue;
      }
      for (int i = 0; i < w; ++i) {
        if (s.score[i] == kInvalid) continue;
        const float weight = c.feather.at<float>(static_cast<int>(s.v[i] + 0.5f), static_cast<int>(s.u[i] + 0.5f));
        if (weight <= 0) continue;
        uint32_t e_rest;
        const uint32_t e_offset = encode(c, s.u[i], s.v[i], static_cast<uint32_t>(ci), e_rest);
        const MapEntry e = make_entry(e_offset, e_rest);
        if (weight > best[i]) {
          second[i] = best[i];
          secondary[i] = primary[i];
          best[i] = weight;
          primary[i] = e;
        } else if (weight > second[i]) {
          second[i] = weight;
          secondary[i] = e;
        }
      }
    }
    if (!blend) {
      for (int i = 0; i < w; ++i) primary[i] = make_entry(offset[i], rest[i]);
      continue;
    }
    uint16_t* pw = &map.primary_weight[static_cast<size_t>(row) * w];
    for (int i = 0; i < w; ++i) {
      const float total = best[i] + second[i];
      pw[i] = secondary[i].cam == kNoCamera || total <= 0
                  ? 256
                  : static_cast<uint16_t>(std::lround(256.0f * best[i] / total));
    }
  }
}

}  // namespace

double FusionMap::coverage() const {
  if (primary.empty()) return 0;
  const auto seen = std::count_if(primary.begin(), primary.end(), [](const MapEntry& e) { return e.cam != kNoCamera; });
  return static_cast<double>(seen) / static_cast<double>(primary.size());
}

FusionMap build_map(const Rig& rig, const View& view) {
  const auto& cameras = rig.cameras();
  if (cameras.size() >= kNoCamera) {
    throw std::invalid_argument("a rig may have at most 254 cameras, this one has " + std::to_string(cameras.size()));
  }
  const ViewSpec& spec = view.spec();
  const std::string frame = spec.frame.empty() ? rig.default_frame() : spec.frame;
  if (!rig.frames().has_frame(frame)) {
    throw std::invalid_argument("view '" + spec.name + "': frame '" + frame + "' is not in the rig");
  }
  const bool blend = spec.fusion == Fusion::kBlend;
  const Pose T_frame_view = spec.T_frame_view();
  std::vector<CameraSetup> setups;
  for (size_t i = 0; i < cameras.size(); ++i) {
    if (!rig.frames().try_lookup(frame, cameras[i].name)) {
      throw std::invalid_argument("view '" + spec.name + "': frame '" + frame + "' is not connected to camera '" +
                                  cameras[i].name + "'");
    }
    setups.push_back(make_setup(rig, i, view, T_frame_view, frame, blend, spec.feather_px));
  }

  FusionMap map;
  map.width = view.width();
  map.height = view.height();
  map.fusion = spec.fusion;
  const size_t n = static_cast<size_t>(map.width) * static_cast<size_t>(map.height);
  map.primary.assign(n, MapEntry{});
  if (blend) {
    map.secondary.assign(n, MapEntry{});
    map.primary_weight.assign(n, 256);
  }
  for (const auto& c : cameras) {
    map.camera_sizes.emplace_back(c.width, c.height);
    map.camera_names.push_back(c.name);
  }

  cv::parallel_for_(cv::Range(0, map.height), [&](const cv::Range& rows) {
    build_rows(view, setups, blend, map, rows.start, rows.end);
  });

  map.camera_used.assign(cameras.size(), false);
  for (const auto* entries : {&map.primary, &map.secondary}) {
    for (const MapEntry& e : *entries) {
      if (e.cam != kNoCamera) map.camera_used[e.cam] = true;
    }
  }
  return map;
}

}  // namespace omniview
