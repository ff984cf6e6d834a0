#include "core/map/adaptive/bands.h"

#include <algorithm>
#include <cmath>

#include "core/map/adaptive/blend_pixels.h"
#include "core/map/adaptive/block_plan.h"
#include "core/map/adaptive/patch_writer.h"
#include "core/map/adaptive/winners.h"

namespace omniview::map_internal {
namespace {

// Grid lines every kBlock pixels, plus the last pixel: 0, 8, ..., n - 1.
std::vector<int> grid_lines(int n) {
  std::vector<int> lines;
  for (int i = 0; i < n - 1; i += kBlock) lines.push_back(i);
  lines.push_back(n - 1);
  return lines;
}

// A full block split in four has a 5x5 lattice: offsets 0, 2, 4, 6, 8 in both axes. Its
// rows 0, 2, 4 are the band's lattice rows, which already hold columns 0, 4, 8.
constexpr int kFine = 5;
constexpr int kFineStep = kBlock / (kFine - 1);
constexpr int kNewOnLatticeRows = 2;  // columns 2 and 6

class BandBuilder {
 public:
  BandBuilder(const View& view, const std::vector<CameraSetup>& setups, FusionMap& map, std::vector<uint8_t>& used,
              const Occlusion* occlusion, bool blend)
      : view_(view), setups_(setups), occlusion_(occlusion), blend_(blend), map_(map), used_(used),
        sampler_(view, setups, occlusion, blend), blend_pixels_(view, setups, occlusion),
        xs_(grid_lines(map.width)),
        ys_(grid_lines(map.height)), exact_columns_(kBlock + 1), shared_columns_(kBlock + 1) {
    const int blocks = static_cast<int>(xs_.size()) - 1;
    for (int j = 0; j < blocks; ++j) columns_.insert(columns_.end(), {xs_[j], (xs_[j] + xs_[j + 1]) / 2});
    columns_.push_back(xs_[blocks]);
  }

  // `continues`: the previous band was built by this builder, so its bottom row is our top.
  void build(int band, bool continues) {
    ya_ = ys_[band], yb_ = ys_[band + 1], yc_ = (ya_ + yb_) / 2;
    row_end_ = band + 2 == static_cast<int>(ys_.size()) ? yb_ + 1 : yb_;  // the last band owns row H-1
    if (continues) {
      std::swap(top_, bottom_);
    } else {
      sample_lattice_row(ya_, top_);
    }
    sample_lattice_row(yc_, middle_);
    sample_lattice_row(yb_, bottom_);
    patches_.clear(), refined_.clear(), black_.clear();
    for (auto& c : exact_columns_) c.clear();
    for (auto& c : shared_columns_) c.clear();
    plan_blocks();
    if (!refined_.empty()) plan_refined_blocks();
    // Every pixel of the band once: interpolated, black or exact.
    write_patches(patches_, setups_, map_);
    for (const BlockLattice& b : black_) {
      for (int y = b.y[0]; y < b.y_end; ++y) std::fill(entry(b.x[0], y), entry(b.x_end, y), kBlackEntry);
    }
    write_exact_rows();
  }

 private:
  void sample_lattice_row(int y, Winners& out) {
    sampler_.sample(y, columns_.data(), static_cast<int>(columns_.size()), out);
  }

  void plan_blocks() {
    const Winners* rows[3] = {&top_, &middle_, &bottom_};
    const int blocks = static_cast<int>(xs_.size()) - 1;
    for (int j = 0; j < blocks; ++j) {
      BlockLattice b;
      for (int k = 0; k < 3; ++k) b.x[k] = columns_[2 * j + k];
      b.y[0] = ya_, b.y[1] = yc_, b.y[2] = yb_;
      b.x_end = j + 1 == blocks ? b.x[2] + 1 : b.x[2];
      b.y_end = row_end_;
      for (int p = 0; p < 3; ++p) {
        for (int k = 0; k < 3; ++k) set_sample(b, p, k, *rows[p], 2 * j + k);
      }
      const BlockPlan plan =
          may_interpolate(b) ? plan_block(b, setups_, Quarters::kAllowed, patches_) : BlockPlan::kExact;
      if (plan == BlockPlan::kBlack) {
        black_.push_back(b);
      } else if (plan != BlockPlan::kExact) {
        used_[b.cam[0][0]] = 1;
      } else if (blend_ && any_shared(b)) {
        add_exact(b, /*shared=*/true);
      } else if (b.x[2] - b.x[0] == kBlock && b.y[2] - b.y[0] == kBlock) {
        refined_.push_back(j);
      } else {
        add_exact(b);
      }
    }
  }

  // The blocks in refined_ on a lattice twice as fine: one biquadratic patch each, or
  // else their 4x4 quarters, each planned like a block.
  void plan_refined_blocks() {
    for (int o = 0; o < kFine; ++o) {  // new samples, one batch per lattice row
      const bool lattice_row = o % 2 == 0;
      fine_columns_.clear();
      for (int j : refined_) {
        for (int k = lattice_row ? 1 : 0; k < kFine; k += lattice_row ? 2 : 1) {
          fine_columns_.push_back(xs_[j] + kFineStep * k);
        }
      }
      sampler_.sample(ya_ + kFineStep * o, fine_columns_.data(), static_cast<int>(fine_columns_.size()), fine_[o]);
    }
    const Winners* lattice_rows[3] = {&top_, &middle_, &bottom_};
    for (size_t r = 0; r < refined_.size(); ++r) {
      const int j = refined_[r];
      FineLattice f;
      for (int i = 0; i < kFine; ++i) f.x[i] = xs_[j] + kFineStep * i, f.y[i] = ya_ + kFineStep * i;
      f.x_end = j + 2 == static_cast<int>(xs_.size()) ? xs_[j + 1] + 1 : xs_[j + 1];
      f.y_end = row_end_;
      for (int o = 0; o < kFine; ++o) {
        for (int k = 0; k < kFine; ++k) {
          if (o % 2 == 1) {
            set_sample(f, o, k, fine_[o], kFine * r + k);
          } else if (k % 2 == 1) {
            set_sample(f, o, k, fine_[o], kNewOnLatticeRows * r + k / 2);
          } else {
            set_sample(f, o, k, *lattice_rows[o / 2], 2 * j + k / 2);
          }
        }
      }
      const bool whole_ok = may_interpolate(f);
      if (whole_ok && try_quadratic(f, setups_, patches_)) {
        used_[f.cam[0][0]] = 1;
        continue;
      }
      for (int qy = 0; qy < 2; ++qy) {
        for (int qx = 0; qx < 2; ++qx) {
          const BlockLattice b = quarter(f, qy, qx);
          const BlockPlan plan = (whole_ok || may_interpolate(b))
                                     ? plan_block(b, setups_, Quarters::kNotAllowed, patches_)
                                     : BlockPlan::kExact;
          if (plan == BlockPlan::kExact) {
            add_exact(b);
          } else if (plan == BlockPlan::kBlack) {
            black_.push_back(b);
          } else {
            used_[b.cam[0][0]] = 1;
          }
        }
      }
    }
  }

  template <int N>
  void set_sample(Lattice<N>& b, int p, int k, const Winners& w, size_t i) const {
    b.u[p][k] = w.u[i], b.v[p][k] = w.v[i], b.cam[p][k] = w.cam[i], b.on_surface[p][k] = w.on_surface[i];
    b.shared[p][k] = blend_ ? w.shared[i] : 0;
    if (keep_points_) {
      b.px[p][k] = w.x[i], b.py[p][k] = w.y[i], b.pz[p][k] = w.z[i], b.better_hidden[p][k] = w.better_hidden[i];
    } else {
      b.better_hidden[p][k] = 0;
    }
  }

  // Blend: two cameras see a sample. A block whose 3x3 lattice has one is exact at once (no
  // fine lattice); one whose fine lattice has one is exact in the quarters that do.
  template <int N>
  bool any_shared(const Lattice<N>& b) const {
    for (int p = 0; p < N; ++p) {
      for (int k = 0; k < N; ++k) {
        if (b.shared[p][k]) return true;
      }
    }
    return false;
  }

  // What measured depth and occlusion add to plan_block's tests: the surface is smooth
  // between the samples (View::smooth_over), no better camera was dropped as hidden at a
  // sample, the occlusion test applies to all of the block's pixels or none, and the
  // winner's covering depth over the block's footprint in its image hides none of it
  // (a thin occluder between two samples would otherwise be interpolated over).
  // And a blend map's block only where one camera sees every sample.
  template <int N>
  bool may_interpolate(const Lattice<N>& b) const {
    if (blend_ && any_shared(b)) return false;
    if (!keep_points_) return true;
    if (!view_.smooth_over(b.x[0], b.y[0], b.x[N - 1], b.y[N - 1], depth_tolerance(b))) return false;
    if (!occlusion_) return true;
    for (int p = 0; p < N; ++p) {
      for (int k = 0; k < N; ++k) {
        if (b.better_hidden[p][k]) return false;
      }
    }
    const uint32_t cam = b.cam[0][0];
    if (cam == kNoCamera) return true;  // plan_block: black only if off the surface everywhere, else exact
    // Judged nowhere in the block: no occlusion applies, the samples tell all. Judged in part: exact.
    const int judged = judged_count(b.x[0], b.y[0], b.x_end - 1, b.y_end - 1);
    if (judged == 0) return true;
    if (judged < (b.x_end - b.x[0]) * (b.y_end - b.y[0])) return false;
    const CameraOccluder& occluder = occlusion_->cameras[cam];
    if (occluder.empty()) return true;
    const CameraSetup& c = setups_[cam];
    float u_min = b.u[0][0], u_max = u_min, v_min = b.v[0][0], v_max = v_min, range_max = 0;
    for (int p = 0; p < N; ++p) {
      for (int k = 0; k < N; ++k) {
        if (b.cam[p][k] != cam) continue;  // plan_block says exact anyway
        u_min = std::min(u_min, b.u[p][k]), u_max = std::max(u_max, b.u[p][k]);
        v_min = std::min(v_min, b.v[p][k]), v_max = std::max(v_max, b.v[p][k]);
        const float x = b.px[p][k], y = b.py[p][k], z = b.pz[p][k];
        const float xc = c.R[0] * x + c.R[1] * y + c.R[2] * z + c.t[0];
        const float yc = c.R[3] * x + c.R[4] * y + c.R[5] * z + c.t[1];
        const float zc = c.R[6] * x + c.R[7] * y + c.R[8] * z + c.t[2];
        range_max = std::max(range_max, std::sqrt(xc * xc + yc * yc + zc * zc));
      }
    }
    // Interpolated coordinates stray from the samples' hull by well under a pixel, and the
    // ranges between samples from theirs by smooth_over's tolerance.
    const int c0 = std::max(0, int(std::max(0.f, u_min - 1) * occluder.inv_cell + occluder.offset));
    const int c1 = std::min(occluder.cols - 1, int((u_max + 1) * occluder.inv_cell + occluder.offset));
    const int r0 = std::max(0, int(std::max(0.f, v_min - 1) * occluder.inv_cell + occluder.offset));
    const int r1 = std::min(occluder.rows - 1, int((v_max + 1) * occluder.inv_cell + occluder.offset));
    float covering = std::numeric_limits<float>::max();
    for (int r = r0; r <= r1; ++r) {
      for (int col = c0; col <= c1; ++col) covering = std::min(covering, occluder.depth[occluder.index(r, col)]);
    }
    return !hidden_behind(range_max * 1.01f, covering, occlusion_->tolerance_rel, occlusion_->tolerance_m);
  }

  // How far (a share of the range) the surface between the samples may stray from their
  // bilinear blend: a range off by a share e moves the point along the view's ray, which
  // the winning camera sees move by e times the shift measured here for 1 % at the
  // block's centre sample. Within kDepthTolerancePx of it, at most 1 % (a camera at the
  // view's place sees no shift at all). A single share for every view failed one way or
  // the other: 0.2 % let a bird's-eye view 4 m up over a floor 1 m from Spot's cameras be
  // interpolated 0.8 px off, while 0.02 % left 25 % of a front view's pixels exact.
  template <int N>
  float depth_tolerance(const Lattice<N>& b) const {
    constexpr float kDepthTolerancePx = 0.03f, kProbe = 0.01f, kMaxShare = 0.01f;
    const uint32_t cam = b.cam[N / 2][N / 2];
    if (cam == kNoCamera) return 0;  // black only where no sample has a surface; then neither may any pixel
    const float x = b.px[N / 2][N / 2], y = b.py[N / 2][N / 2], z = b.pz[N / 2][N / 2];
    const float xs[2] = {x, x * (1 + kProbe)}, ys[2] = {y, y * (1 + kProbe)}, zs[2] = {z, z * (1 + kProbe)};
    const uint8_t valid[2] = {1, 1};
    float u[2] = {}, v[2] = {}, score[2] = {};
    project_camera_row(setups_[cam], 2, xs, ys, zs, valid, u, v, score);
    if (score[0] == kInvalid || score[1] == kInvalid) return 0;
    const float shift = std::max(std::abs(u[1] - u[0]), std::abs(v[1] - v[0]));
    return shift * kMaxShare <= kDepthTolerancePx * kProbe ? kMaxShare : kDepthTolerancePx * kProbe / shift;
  }

  // Pixels of [x0, x1] x [y0, y1] the occlusion test applies to (Occlusion::judged).
  int judged_count(int x0, int y0, int x1, int y1) const {
    if (occlusion_->judged.empty()) return (x1 - x0 + 1) * (y1 - y0 + 1);
    int n = 0;
    for (int y = y0; y <= y1; ++y) {
      const uint8_t* row = &occlusion_->judged[static_cast<size_t>(y) * map_.width];
      for (int x = x0; x <= x1; ++x) n += row[x] != 0;
    }
    return n;
  }

  // `shared`: a blend map's block two cameras see at some sample: the blend rule at every
  // pixel, without first asking the winner sampler whether one camera sees it.
  void add_exact(const BlockLattice& b, bool shared = false) {
    auto& rows = shared ? shared_columns_ : exact_columns_;
    for (int y = b.y[0]; y < b.y_end; ++y) {
      std::vector<int>& columns = rows[y - ya_];
      for (int x = b.x[0]; x < b.x_end; ++x) columns.push_back(x);
    }
  }

  MapEntry* entry(int x, int y) { return &map_.primary[static_cast<size_t>(y) * map_.width + x]; }

  void write_exact_rows() {
    for (int y = ya_; y < row_end_; ++y) {
      const std::vector<int>& columns = exact_columns_[y - ya_];
      std::vector<int>& shared = shared_columns_[y - ya_];
      const int n = static_cast<int>(columns.size());
      if (n > 0) sampler_.sample(y, columns.data(), n, exact_);
      MapEntry* row = entry(0, y);
      for (int i = 0; i < n; ++i) {
        // Blend: where one camera sees the pixel, its entry at full weight is the blend's
        // (secondary and weight stay as allocated); where two do, the blend rule's entries.
        if (blend_ && exact_.shared[i]) {
          shared.push_back(columns[i]);
          continue;
        }
        const uint32_t cam = exact_.cam[i];
        if (cam == kNoCamera) {
          row[columns[i]] = kBlackEntry;
          continue;
        }
        uint32_t rest;
        const uint32_t offset = encode(setups_[cam].limits, exact_.u[i], exact_.v[i], cam, rest);
        row[columns[i]] = make_entry(offset, rest);
        used_[cam] = 1;
      }
      blend_pixels_.write(y, shared.data(), static_cast<int>(shared.size()), map_, used_);
    }
  }

  const View& view_;
  const std::vector<CameraSetup>& setups_;
  const Occlusion* occlusion_;
  const bool blend_;
  const bool keep_points_ = occlusion_ || view_.measured();  // the samples' surface points (Winners)
  FusionMap& map_;
  std::vector<uint8_t>& used_;
  WinnerSampler sampler_;
  BlendPixels blend_pixels_;  // blend: the exact pixels' entries
  const std::vector<int> xs_, ys_;
  std::vector<int> columns_;  // lattice columns: grid lines at even indices, midpoints at odd
  int ya_ = 0, yc_ = 0, yb_ = 0, row_end_ = 0;
  Winners top_, middle_, bottom_;  // exact winners on the band's lattice rows
  std::vector<Patch> patches_;
  std::vector<std::vector<int>> exact_columns_;  // per row of the band: pixels computed exactly
  std::vector<int> refined_;                     // blocks given the fine lattice
  std::vector<BlockLattice> black_;              // blocks off the view's surface
  std::vector<int> fine_columns_;
  std::vector<std::vector<int>> shared_columns_;  // blend: per row of the band, the pixels two cameras see
  Winners fine_[kFine];  // the split blocks' new samples, per row of their 5x5 lattice
  Winners exact_;
};

}  // namespace

void build_bands_adaptive(const View& view, const std::vector<CameraSetup>& setups, FusionMap& map, int band_begin,
                          int band_end, std::vector<uint8_t>& used, const Occlusion* occlusion, bool blend) {
  BandBuilder builder(view, setups, map, used, occlusion, blend);
  for (int band = band_begin; band < band_end; ++band) builder.build(band, band > band_begin);
}

}  // namespace omniview::map_internal
