// A view whose surface follows measured geometry (`depth: measured`, DESIGN.md "Measured
// depth"): each pixel's surface point lies on its ray at the range the measured points give
// (splatted with a z-buffer, gaps joined), the view's fixed surface where nothing was
// measured near the ray, blended between the two. It is a View like any other, so
// build_map, point_to_pixel and the clients' overlays work on it unchanged.
//
//   DepthSurface surface(spec);                                 // once per view change
//   auto view = surface.update(points, T_view_points, &stats);  // per geometry update
//   build_map(rig, *view, MapPrecision::kAdaptive, Sampling::kFootprint, &occlusion);
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/depth/depth_options.h"
#include "core/depth/surface_lattice.h"
#include "core/depth/view_rays.h"
#include "core/geometry/pose.h"
#include "core/view/view.h"

namespace omniview {

class MeasuredDepthView : public View {
 public:
  // `range`: per pixel along its ray (0: no surface point); `measured`: share of measured
  // depth per pixel, 0..255; `sampled`: 1 where a point itself gave the range, not the gap
  // fill (empty: nowhere).
  MeasuredDepthView(std::shared_ptr<const ViewRays> rays, std::vector<float> range, std::vector<uint8_t> measured,
                    std::vector<uint8_t> sampled = {});

  bool pixel_to_direction(double u, double v, Vec3& dir) const override;
  bool point_to_pixel(const Vec3& point, Vec2& uv) const override;

  // Range along pixel (u, v)'s ray (0: none), and how much of it is measured (0..255).
  float range_at(int u, int v) const { return range_[size_t(v) * width() + u]; }
  uint8_t measured_at(int u, int v) const { return measured_[size_t(v) * width() + u]; }
  // For Occlusion::judged: where the surface is geometry, not a guess: measured, or the
  // fixed surface where it is the ground (the floor behind a pillar a camera sees the pillar
  // over). Not the blend band, nor a fixed plane, cylinder or sphere: a point of those a
  // camera sees behind a measured object is most often that object going on past its last
  // measured ring, and black there would hide what the camera plainly sees.
  // Pixels within kJudgedMargin of one that is not judged are not judged either, nor those
  // within kEdgeMarginDeg of a surface nearer by more than kEdgeStep where less than
  // kDenseShare of the pixels around them were sampled (a lidar's edges are uncertain).
  std::vector<uint8_t> occlusion_judged() const;
  static constexpr int kJudgedMargin = 3;
  static constexpr double kEdgeMarginDeg = 2.0;  // a VLP-16's ring spacing
  static constexpr float kEdgeStep = 0.1f;  // as DepthOptions::max_step_rel: what the gap fill calls a step
  static constexpr float kDenseShare = 0.5f;
  // Fraction of the view's pixels that stand on measured depth (blend band included).
  double measured_fraction() const;
  // Every pixel's range within tolerance_rel of the bilinear blend of the four corners'
  // ranges, or all of them without a surface point.
  bool smooth_over(int x0, int y0, int x1, int y1, float tolerance_rel) const override;
  bool measured() const override { return true; }

 protected:
  double surface_range(const Vec3& unit_dir) const override;
  void surface_row_points(int v, float* x, float* y, float* z, uint8_t* valid) const override;
  void surface_points_at(int v, const int* columns, int n, float* x, float* y, float* z,
                         uint8_t* valid) const override;

 private:
  std::shared_ptr<const ViewRays> rays_;
  std::vector<float> range_;
  std::vector<uint8_t> measured_;
  std::vector<uint8_t> sampled_;
};

// Makes MeasuredDepthViews of one view spec from successive sets of points: the rays, the
// fixed surface and the lattice are computed once, each update costs a splat, a gap fill
// and a blend on the lattice (surface_lattice.h) and a pass over the view's pixels.
class DepthSurface {
 public:
  // Throws std::invalid_argument for an invalid spec (validate()).
  explicit DepthSurface(const ViewSpec& spec, const DepthOptions& options = {});

  // `points` in some frame P; T_view_points places P in the view frame. Non-finite points
  // are skipped and counted in `stats` (optional). No points: the fixed surface.
  // `completion` (optional, in the same frame): points that complete the measured ones
  // (column_completion.h), taken only where the measured surface leaves the view empty and
  // joined there (the measured surface stays as the points alone make it).
  std::shared_ptr<const MeasuredDepthView> update(const std::vector<Eigen::Vector3f>& points,
                                                  const Pose& T_view_points, DepthStats* stats = nullptr,
                                                  const std::vector<Eigen::Vector3f>* completion = nullptr) const;

  const ViewRays& rays() const { return *rays_; }
  const SurfaceLattice& lattice() const { return lattice_; }
  // At least this many points per view pixel inside the view: the surface is made on the
  // view's own pixels, not the lattice (a depth per pixel resolves finer than a cell).
  static constexpr double kDenseSamplesPerPixel = 0.25;

 private:
  std::shared_ptr<const ViewRays> rays_;
  SurfaceLattice lattice_;
  DepthOptions options_;
};

}  // namespace omniview
