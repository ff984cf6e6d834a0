#include "core/depth/surface_lattice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <numeric>

#include <opencv2/core/utility.hpp>

#include "core/map/parallel_rows.h"

namespace omniview {
namespace {

// Where the lattice's cell for a view pixel (u, v) is: a ray of the view projected by the
// lattice's view. False where either has no ray.
bool lattice_position(const View& view, const View& lattice, double u, double v, Vec2& uv) {
  Vec3 dir;
  return view.pixel_to_direction(u, v, dir) && lattice.point_to_pixel(dir, uv);
}

}  // namespace

SurfaceLattice make_surface_lattice(std::shared_ptr<const ViewRays> view, double cell_deg) {
  SurfaceLattice lattice;
  const int w = view->width, h = view->height;
  lattice.cells = view;
  lattice.column_at.resize(w);
  lattice.row_at.resize(h);
  std::iota(lattice.column_at.begin(), lattice.column_at.end(), 0.f);
  std::iota(lattice.row_at.begin(), lattice.row_at.end(), 0.f);
  const int c = static_cast<int>(std::lround(cell_deg * M_PI / 180 / view->pixel_rad));
  if (c < 2) return lattice;

  ViewSpec spec = view->view->spec();
  spec.width = (w + c - 1) / c;
  spec.height = (h + c - 1) / c;
  spec.depth = Depth::kFixed;  // the lattice's own fixed surface is the view's, sampled coarser
  std::shared_ptr<const View> coarse;
  try {
    coarse = View::create(spec);
  } catch (const std::exception&) {
    return lattice;  // a spec that cannot be made smaller: the view's own pixels
  }
  // Each column's lattice position from the first of a few rows where it has a ray (the
  // middle row first), each row's likewise; then checked across the whole image, so a
  // projection that is not separable falls back instead of misplacing.
  constexpr int kChecks = 17;
  std::vector<double> probe_rows = {(h - 1) / 2.0}, probe_columns = {(w - 1) / 2.0};
  for (int k = 0; k < kChecks; ++k) {
    probe_rows.push_back(double(h - 1) * k / (kChecks - 1));
    probe_columns.push_back(double(w - 1) * k / (kChecks - 1));
  }
  const auto position = [&](double u, double v, const std::vector<double>& others, bool column, float& out) {
    Vec2 uv;
    for (double other : others) {
      if (lattice_position(*view->view, *coarse, column ? u : other, column ? other : v, uv)) {
        out = static_cast<float>(column ? uv.x() : uv.y());
        return true;
      }
    }
    return false;
  };
  // A column or row with no ray at any of them (above a bird's-eye view's horizon, beside a
  // fisheye's image circle) has no pixel that needs a cell: it takes its neighbour's.
  const auto axis = [&](int count, bool column, std::vector<float>& out) {
    out.assign(count, std::numeric_limits<float>::quiet_NaN());
    int found = 0;
    for (int k = 0; k < count; ++k) {
      found += column ? position(k, 0, probe_rows, true, out[k]) : position(0, k, probe_columns, false, out[k]);
    }
    if (found == 0) return false;
    for (int k = 1; k < count; ++k) {
      if (std::isnan(out[k])) out[k] = out[k - 1];
    }
    for (int k = count - 2; k >= 0; --k) {
      if (std::isnan(out[k])) out[k] = out[k + 1];
    }
    return true;
  };
  std::vector<float> columns, rows;
  if (!axis(w, true, columns) || !axis(h, false, rows)) return lattice;
  Vec2 uv;
  constexpr double kTolerance = 0.25;  // cells
  for (int j = 0; j < kChecks; ++j) {
    for (int k = 0; k < kChecks; ++k) {
      const int u = (w - 1) * k / (kChecks - 1), v = (h - 1) * j / (kChecks - 1);
      if (!lattice_position(*view->view, *coarse, u, v, uv)) continue;  // no ray there (a fisheye's corner)
      if (std::abs(uv.x() - columns[u]) > kTolerance || std::abs(uv.y() - rows[v]) > kTolerance) return lattice;
    }
  }
  lattice.cells = make_view_rays(std::move(coarse));
  lattice.cell = c;
  lattice.column_at = std::move(columns);
  lattice.row_at = std::move(rows);
  return lattice;
}

UpsampledSurface upsample_surface(const SurfaceLattice& lattice, const ViewRays& view, const BlendedSurface& cells,
                                  const std::vector<uint8_t>& sampled, const DepthOptions& options) {
  const ViewRays& lat = *lattice.cells;
  const int W = lat.width, H = lat.height, w = view.width, h = view.height;
  UpsampledSurface out;
  out.range.resize(view.size());
  out.measured.resize(view.size());
  out.sampled.resize(view.size());
  const float rel = static_cast<float>(options.max_step_rel), abs_m = static_cast<float>(options.max_step_m);
  // A pixel's cell and the four around it, per column (the same for every row).
  std::vector<int> u0(w), u1(w), un(w);
  std::vector<float> tu(w);
  for (int u = 0; u < w; ++u) {
    const float f = std::clamp(lattice.column_at[u], 0.f, float(W - 1));
    u0[u] = static_cast<int>(f);
    u1[u] = std::min(u0[u] + 1, W - 1);
    tu[u] = f - float(u0[u]);
    un[u] = tu[u] < 0.5f ? u0[u] : u1[u];
  }
  std::mutex counts;
  parallel_rows(cv::Range(0, h), [&](const cv::Range& rows) {
    size_t my_measured = 0, my_blended = 0;
    for (int v = rows.start; v < rows.end; ++v) {
      const float fv = std::clamp(lattice.row_at[v], 0.f, float(H - 1));
      const int v0 = static_cast<int>(fv), v1 = std::min(v0 + 1, H - 1);
      const float tv = fv - float(v0);
      const size_t top = size_t(v0) * W, bottom = size_t(v1) * W, near_row = tv < 0.5f ? top : bottom;
      for (int u = 0; u < w; ++u) {
        const size_t i = size_t(v) * w + u;
        const size_t nearest = near_row + un[u];
        const uint8_t share = cells.measured[nearest];
        const float fixed = view.fixed_range[i];
        float range = fixed;  // 0 where the fixed surface has no point either
        uint8_t measured = 0;
        if (!view.valid[i]) {
          range = 0.f;
        } else if (share == 255) {
          range = cells.range[nearest];
          const size_t a = top + u0[u], b = top + u1[u], c = bottom + u0[u], d = bottom + u1[u];
          if ((cells.measured[a] & cells.measured[b] & cells.measured[c] & cells.measured[d]) == 255) {
            const float ra = cells.range[a], rb = cells.range[b], rc = cells.range[c], rd = cells.range[d];
            const float lo = std::min({ra, rb, rc, rd}), hi = std::max({ra, rb, rc, rd});
            if (hi - lo <= rel * lo + abs_m) {  // one surface: smooth between the cells
              const float upper = ra + (rb - ra) * tu[u], lower = rc + (rd - rc) * tu[u];
              range = upper + (lower - upper) * tv;
            }
          }
          measured = 255;
          ++my_measured;
        } else if (share > 0 && fixed > 0.f && lat.fixed_range[nearest] > 0.f && cells.range[nearest] > 0.f) {
          // The cell's blend of measured and fixed (fixed / range) on the pixel's own fixed range.
          range = fixed * (cells.range[nearest] / lat.fixed_range[nearest]);
          measured = share;
          ++my_blended;
        }
        out.range[i] = range;
        out.measured[i] = measured;
        out.sampled[i] = measured == 255 && sampled[nearest];
      }
    }
    std::lock_guard lock(counts);
    out.measured_pixels += my_measured;
    out.blended_pixels += my_blended;
  });
  return out;
}

}  // namespace omniview
