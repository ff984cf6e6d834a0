// Adaptive map building for the nearest-centre policy.
//
// Camera models and surfaces are smooth, so inside most 8x8 blocks of the output the
// source coordinates are almost exactly a bilinear function of the pixel position. The
// builder evaluates the models exactly at the block corners, edge midpoints and centres
// (under a tenth of the pixels) and interpolates inside a block only when all agree:
//   - the same camera wins at all four corners and at the centre;
//   - at the centre and the four edge midpoints the interpolated coordinates lie within
//     kTolerancePx of the exact ones (bilinear error peaks there for smooth maps; the
//     midpoints catch saddle-shaped maps whose error cancels at the centre);
//   - that camera's mask, if it has one, allows every interpolated pixel.
// Every other block (seams, coverage edges, fisheye circles, masks) is computed pixel by
// pixel. The image border needs no test: a bilinear patch whose corners lie inside the
// image stays inside it. Near a seam the interpolated block may keep a camera whose
// neighbour would win by a hair; both see the point, so the picture is the same.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/map/map_kernels.h"
#include "core/map/multiversion.h"

namespace omniview::map_internal {
namespace {

constexpr float kTolerancePx = 0.05f;

// Grid lines every kBlock pixels, plus the last pixel: 0, 8, ..., n - 1.
std::vector<int> grid_lines(int n) {
  std::vector<int> lines;
  for (int i = 0; i < n - 1; i += kBlock) lines.push_back(i);
  lines.push_back(n - 1);
  return lines;
}

// The exact winner (camera and coordinates) at chosen pixels of one row.
struct Winners {
  std::vector<float> u, v;
  std::vector<int> cam;  // kNoCamera where no camera sees the pixel
  std::vector<uint8_t> on_surface;  // the view's surface exists there (not a fisheye corner)
};

class RowSampler {
 public:
  RowSampler(const View& view, const std::vector<CameraSetup>& setups)
      : view_(view), setups_(setups), row_(view.width()) {}

  void sample(int row, const std::vector<int>& columns, Winners& out) {
    view_.row_points(row, row_.x.data(), row_.y.data(), row_.z.data(), row_.valid.data());
    const size_t n = columns.size();
    x_.resize(n), y_.resize(n), z_.resize(n), valid_.resize(n), u_.resize(n), v_.resize(n), score_.resize(n);
    best_.assign(n, kInvalid);
    out.u.assign(n, 0), out.v.assign(n, 0), out.cam.assign(n, kNoCamera);
    for (size_t i = 0; i < n; ++i) {
      const int c = columns[i];
      x_[i] = row_.x[c], y_[i] = row_.y[c], z_[i] = row_.z[c], valid_[i] = row_.valid[c];
    }
    out.on_surface = valid_;
    for (size_t ci = 0; ci < setups_.size(); ++ci) {
      const CameraSetup& c = setups_[ci];
      std::visit([&](const auto& model) {
        project_row(model, c, static_cast<int>(n), x_.data(), y_.data(), z_.data(), valid_.data(), u_.data(),
                    v_.data(), score_.data());
      }, c.camera->model);
      for (size_t i = 0; i < n; ++i) {
        if (score_[i] < best_[i] && mask_allows(*c.camera, u_[i], v_[i])) {
          best_[i] = score_[i];
          out.u[i] = u_[i], out.v[i] = v_[i], out.cam[i] = static_cast<int>(ci);
        }
      }
    }
  }

 private:
  const View& view_;
  const std::vector<CameraSetup>& setups_;
  RowScratch row_;
  std::vector<float> x_, y_, z_, u_, v_, score_, best_;
  std::vector<uint8_t> valid_;
};

// Pixel-by-pixel fallback for the blocks interpolation may not cover.
class ExactBlocks {
 public:
  ExactBlocks(const View& view, const std::vector<CameraSetup>& setups, FusionMap& map, int row_begin, int row_end,
              std::vector<uint8_t>& used)
      : view_(view), setups_(setups), map_(map), row_begin_(row_begin), row_end_(row_end), used_(used) {}

  // Columns [x_begin, x_end) of every row of the band.
  void compute(int x_begin, int x_end) {
    if (rows_.empty()) {  // surface points of the band's rows, on first need
      for (int y = row_begin_; y < row_end_; ++y) {
        rows_.emplace_back(map_.width);
        view_.row_points(y, rows_.back().x.data(), rows_.back().y.data(), rows_.back().z.data(),
                         rows_.back().valid.data());
      }
    }
    const int n = x_end - x_begin;
    best_.resize(n), offset_.resize(n), rest_.resize(n);
    for (int y = row_begin_; y < row_end_; ++y) {
      RowScratch& r = rows_[y - row_begin_];
      std::fill(best_.begin(), best_.end(), kInvalid);
      std::fill(rest_.begin(), rest_.end(), kNoRest);
      for (size_t ci = 0; ci < setups_.size(); ++ci) {
        const CameraSetup& c = setups_[ci];
        float* u = r.u.data() + x_begin;
        float* v = r.v.data() + x_begin;
        float* score = r.score.data() + x_begin;
        std::visit([&](const auto& model) {
          project_row(model, c, n, r.x.data() + x_begin, r.y.data() + x_begin, r.z.data() + x_begin,
                      r.valid.data() + x_begin, u, v, score);
        }, c.camera->model);
        if (!c.camera->mask.empty()) {
          for (int i = 0; i < n; ++i) {
            if (score[i] != kInvalid && !mask_allows(*c.camera, u[i], v[i])) score[i] = kInvalid;
          }
        }
        select_nearest(c, static_cast<uint32_t>(ci), n, u, v, score, best_.data(), offset_.data(), rest_.data());
      }
      MapEntry* out = &map_.primary[static_cast<size_t>(y) * map_.width + x_begin];
      for (int i = 0; i < n; ++i) {
        out[i] = make_entry(offset_[i], rest_[i]);
        if (out[i].cam != kNoCamera) used_[out[i].cam] = 1;
      }
    }
  }

 private:
  const View& view_;
  const std::vector<CameraSetup>& setups_;
  FusionMap& map_;
  int row_begin_, row_end_;
  std::vector<uint8_t>& used_;
  std::vector<RowScratch> rows_;
  std::vector<float> best_;
  std::vector<uint32_t> offset_, rest_;
};

// A bilinear patch of source coordinates over output pixels [x_begin, x_end) x
// [y_begin, y_end), from exact values at its corners (x0, y0) ... (x1, y1).
struct Patch {
  int x0, x1, y0, y1;
  float u00, u10, u01, u11, v00, v10, v01, v11;  // uXY: X = 0 left / 1 right, Y = 0 top / 1 bottom
  int x_begin, x_end, y_begin, y_end;

  // Writes the patch's source coordinates and camera into band buffers (row stride
  // `stride`, first row `band_top`); encoding then runs over whole rows at once.
  void rasterize(uint8_t cam, int band_top, int stride, float* u, float* v, uint8_t* cams) const {
    const float inv_w = 1.0f / static_cast<float>(x1 - x0), inv_h = 1.0f / static_cast<float>(y1 - y0);
    for (int y = y_begin; y < y_end; ++y) {
      const float ty = static_cast<float>(y - y0) * inv_h;
      const float ul = u00 + (u01 - u00) * ty, ur = u10 + (u11 - u10) * ty;
      const float vl = v00 + (v01 - v00) * ty, vr = v10 + (v11 - v10) * ty;
      const float du = (ur - ul) * inv_w, dv = (vr - vl) * inv_w;
      const size_t row = static_cast<size_t>(y - band_top) * stride;
      for (int x = x_begin; x < x_end; ++x) {
        const float t = static_cast<float>(x - x0);
        u[row + x] = ul + du * t;
        v[row + x] = vl + dv * t;
        cams[row + x] = cam;
      }
    }
  }

  template <typename F>
  void for_each(F&& f) const {  // f(x, y, u, v)
    const float inv_w = 1.0f / static_cast<float>(x1 - x0), inv_h = 1.0f / static_cast<float>(y1 - y0);
    for (int y = y_begin; y < y_end; ++y) {
      const float ty = static_cast<float>(y - y0) * inv_h;
      const float ul = u00 + (u01 - u00) * ty, ur = u10 + (u11 - u10) * ty;
      const float vl = v00 + (v01 - v00) * ty, vr = v10 + (v11 - v10) * ty;
      for (int x = x_begin; x < x_end; ++x) {
        const float tx = static_cast<float>(x - x0) * inv_w;
        f(x, y, ul + (ur - ul) * tx, vl + (vr - vl) * tx);
      }
    }
  }
};

enum class Plan { kWhole, kQuarters, kBlack, kExact };

// Encodes the interpolated pixels of a band. When every camera has the same image size
// (the usual rig) the limits are one set of constants and each row is a single loop GCC
// vectorises; mixed sizes take a per-pixel lookup.
void encode_rows(const std::vector<CameraSetup>& setups, int row_begin, int row_end, const float* u, const float* v,
                 const uint8_t* cams, FusionMap& map) {
  bool uniform = true;
  for (const auto& c : setups) {
    uniform = uniform && c.limits.width_px == setups[0].limits.width_px && c.limits.max_v == setups[0].limits.max_v;
  }
  const int w = map.width;
  std::vector<uint32_t> words(2 * static_cast<size_t>(w));
  for (int y = row_begin; y < row_end; ++y) {
    const size_t row = static_cast<size_t>(y - row_begin) * w;
    MapEntry* out = &map.primary[static_cast<size_t>(y) * w];
    if (uniform) {
      const SampleLimits limits = setups[0].limits;
      // MapEntry as two 32-bit words: offset, then fx | fy << 8 | cam << 16.
      uint32_t* __restrict dst = words.data();
      const uint8_t* __restrict row_cams = cams + row;
      const float* __restrict row_u = u + row;
      const float* __restrict row_v = v + row;
      std::memcpy(dst, out, w * sizeof(uint64_t));  // exact and black blocks are already there
      for (int x = 0; x < w; ++x) {
        const uint32_t cam = row_cams[x];
        uint32_t rest;
        const uint32_t offset = encode(limits, row_u[x], row_v[x], cam, rest);
        const uint32_t take = 0u - static_cast<uint32_t>(cam != kNoCamera);  // masks, not ?: (SIMD)
        dst[2 * x] = (offset & take) | (dst[2 * x] & ~take);
        dst[2 * x + 1] = (rest & take) | (dst[2 * x + 1] & ~take);
      }
      std::memcpy(out, dst, w * sizeof(uint64_t));
    } else {
      for (int x = 0; x < w; ++x) {
        const uint8_t cam = cams[row + x];
        if (cam == kNoCamera) continue;
        uint32_t rest;
        const uint32_t offset = encode(setups[cam].limits, u[row + x], v[row + x], cam, rest);
        out[x] = make_entry(offset, rest);
      }
    }
  }
}

}  // namespace

OMNIVIEW_MULTIVERSION
void build_band_adaptive(const View& view, const std::vector<CameraSetup>& setups, FusionMap& map, int band,
                         std::vector<uint8_t>& used) {
  const std::vector<int> xs = grid_lines(map.width), ys = grid_lines(map.height);
  const int ya = ys[band], yb = ys[band + 1], yc = (ya + yb) / 2;
  const int row_end = band + 2 == static_cast<int>(ys.size()) ? yb + 1 : yb;  // the last band owns row H-1
  const int blocks = static_cast<int>(xs.size()) - 1;

  // Exact samples on a 3x3 lattice per block: grid lines at even indices, midpoints at odd.
  std::vector<int> columns;
  for (int j = 0; j < blocks; ++j) columns.insert(columns.end(), {xs[j], (xs[j] + xs[j + 1]) / 2});
  columns.push_back(xs[blocks]);
  RowSampler sampler(view, setups);
  Winners top, middle, bottom;
  sampler.sample(ya, columns, top);
  sampler.sample(yc, columns, middle);
  sampler.sample(yb, columns, bottom);
  const Winners* rows[3] = {&top, &middle, &bottom};
  const int row_y[3] = {ya, yc, yb};

  // Patch between lattice points (column index a..b, row index p..q) over the given pixels.
  const auto patch = [&](int a, int b, int p, int q, int x_begin, int x_end, int y_begin, int y_end) {
    return Patch{columns[a], columns[b], row_y[p], row_y[q],
                 rows[p]->u[a], rows[p]->u[b], rows[q]->u[a], rows[q]->u[b],
                 rows[p]->v[a], rows[p]->v[b], rows[q]->v[a], rows[q]->v[b],
                 x_begin, x_end, y_begin, y_end};
  };

  ExactBlocks exact(view, setups, map, ya, row_end, used);
  // Interpolated pixels: coordinates and camera per pixel of the band; kNoCamera elsewhere.
  const size_t band_pixels = static_cast<size_t>(row_end - ya) * map.width;
  std::vector<float> band_u(band_pixels), band_v(band_pixels);
  std::vector<uint8_t> band_cam(band_pixels, kNoCamera);
  int exact_run_begin = -1;  // consecutive exact blocks are computed as one run
  for (int j = 0; j <= blocks; ++j) {
    Plan plan = Plan::kExact;
    int cam = kNoCamera;
    std::vector<Patch> patches;
    const int x_begin = j < blocks ? xs[j] : 0, x_end = j + 1 == blocks ? xs[j + 1] + 1 : (j < blocks ? xs[j + 1] : 0);
    if (j < blocks) {
      const int l = 2 * j, m = l + 1, r = l + 2;
      cam = top.cam[l];
      bool same = cam != kNoCamera, off_surface = true;
      for (const Winners* w : rows) {
        for (int k : {l, m, r}) same = same && w->cam[k] == cam, off_surface = off_surface && !w->on_surface[k];
      }
      if (same) {
        // Largest gap between the whole-block interpolation and the exact midpoint samples.
        const Patch whole = patch(l, r, 0, 2, x_begin, x_end, ya, row_end);
        float error = 0;
        for (int p = 0; p < 3; ++p) {
          for (int k : {l, m, r}) {
            if ((p != 1) && (k != m)) continue;  // corners are exact by construction
            const float tx = static_cast<float>(columns[k] - columns[l]) / static_cast<float>(columns[r] - columns[l]);
            const float ty = static_cast<float>(row_y[p] - ya) / static_cast<float>(yb - ya);
            const float ul = whole.u00 + (whole.u01 - whole.u00) * ty, ur = whole.u10 + (whole.u11 - whole.u10) * ty;
            const float vl = whole.v00 + (whole.v01 - whole.v00) * ty, vr = whole.v10 + (whole.v11 - whole.v10) * ty;
            error = std::max({error, std::abs(ul + (ur - ul) * tx - rows[p]->u[k]),
                              std::abs(vl + (vr - vl) * tx - rows[p]->v[k])});
          }
        }
        // Bilinear error shrinks with the square of the block size: a block within four
        // times the tolerance is within it when split into quarters at the exact midpoints.
        if (error <= kTolerancePx) {
          plan = Plan::kWhole;
          patches = {whole};
        } else if (error <= 4 * kTolerancePx) {
          plan = Plan::kQuarters;
          const int xm = columns[m];
          patches = {patch(l, m, 0, 1, x_begin, xm, ya, yc), patch(m, r, 0, 1, xm, x_end, ya, yc),
                     patch(l, m, 1, 2, x_begin, xm, yc, row_end), patch(m, r, 1, 2, xm, x_end, yc, row_end)};
        }
        if (plan != Plan::kExact && !setups[cam].camera->mask.empty()) {
          bool masked = false;
          for (const Patch& pt : patches) {
            pt.for_each([&](int, int, float u, float v) { masked = masked || !mask_allows(*setups[cam].camera, u, v); });
          }
          if (masked) plan = Plan::kExact;
        }
      } else if (off_surface) {
        plan = Plan::kBlack;  // off the view's surface at all nine samples (a fisheye view's corners)
      }
    }
    // Flush the run of exact blocks before anything else (or at the end).
    if (exact_run_begin >= 0 && (plan != Plan::kExact || j == blocks)) {
      exact.compute(exact_run_begin, j < blocks ? x_begin : map.width);
      exact_run_begin = -1;
    }
    if (j == blocks) break;
    if (plan == Plan::kExact) {
      if (exact_run_begin < 0) exact_run_begin = x_begin;
      continue;
    }
    if (plan == Plan::kBlack) {
      for (int y = ya; y < row_end; ++y) {
        std::fill_n(&map.primary[static_cast<size_t>(y) * map.width + x_begin], x_end - x_begin, kBlackEntry);
      }
      continue;
    }
    for (const Patch& pt : patches) {
      pt.rasterize(static_cast<uint8_t>(cam), ya, map.width, band_u.data(), band_v.data(), band_cam.data());
    }
    used[cam] = 1;
  }
  encode_rows(setups, ya, row_end, band_u.data(), band_v.data(), band_cam.data(), map);
}

}  // namespace omniview::map_internal
