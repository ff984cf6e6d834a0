#include "core/depth/range_splat.h"

#include <algorithm>
#include <cmath>

namespace omniview {
namespace {

// A pinhole view's projection in float, inlined: the generic View::point_to_pixel costs a
// virtual call and double arithmetic per point, a third of a 300 k-point update.
struct PinholeProjection {
  float f, cx, cy, max_u, max_v;
  bool operator()(float x, float y, float z, float& fu, float& fv) const {
    if (!(x > 1e-6f)) return false;
    const float inv = f / x;
    fu = cx - y * inv, fv = cy - z * inv;
    return fu >= -0.5f && fv >= -0.5f && fu < max_u && fv < max_v;  // NaN fails too
  }
};

// A point of the view frame to its pixel position (fractional), false outside the image.
class Projector {
 public:
  explicit Projector(const ViewRays& rays) : rays_(rays), view_(*rays.view) {
    const ViewSpec& spec = view_.spec();
    pinhole_ = spec.type == ViewType::kPerspective || spec.type == ViewType::kBirdseye;
    const float f = static_cast<float>((spec.width / 2.0) / std::tan(spec.hfov_deg * M_PI / 360.0));
    project_ = {f, static_cast<float>((spec.width - 1) / 2.0), static_cast<float>((spec.height - 1) / 2.0),
                rays.width - 0.5f, rays.height - 0.5f};
  }
  bool operator()(const Eigen::Vector3f& p, float& fu, float& fv) const {
    if (pinhole_) return project_(p.x(), p.y(), p.z(), fu, fv);
    Vec2 uv;
    if (!view_.point_to_pixel(p.cast<double>(), uv)) return false;
    fu = static_cast<float>(uv.x()), fv = static_cast<float>(uv.y());
    return fu >= -0.5f && fv >= -0.5f && fu < rays_.width - 0.5f && fv < rays_.height - 0.5f;
  }

 private:
  const ViewRays& rays_;
  const View& view_;
  bool pinhole_ = false;
  PinholeProjection project_{};
};

// The nearest range wins; counts newly splatted pixels.
inline void keep_nearest(std::vector<float>& range, size_t i, float r, DepthStats& stats) {
  float& cell = range[i];
  if (cell == 0.f) ++stats.splatted_pixels;
  if (cell == 0.f || r < cell) cell = r;
}

// A point of the view frame into its pixel, or counted as outside the view.
void splat_point(const Projector& project, const ViewRays& rays, const Eigen::Vector3f& p, std::vector<float>& range,
                 DepthStats& stats) {
  float fu = 0, fv = 0;
  const float r = p.norm();
  if (!project(p, fu, fv) || !(r > 0)) {
    ++stats.outside_view;
    return;
  }
  const size_t i = size_t(static_cast<int>(fv + 0.5f)) * rays.width + static_cast<int>(fu + 0.5f);
  if (!rays.valid[i]) {
    ++stats.outside_view;
    return;
  }
  keep_nearest(range, i, r, stats);
}

}  // namespace

std::vector<float> splat_points(const ViewRays& rays, const std::vector<Eigen::Vector3f>& points,
                                const Pose& T_view_points, DepthStats& stats) {
  std::vector<float> range(rays.size(), 0.f);
  const Projector project(rays);
  const Eigen::Matrix3f R = T_view_points.linear().cast<float>();
  const Eigen::Vector3f t = T_view_points.translation().cast<float>();
  stats.points += points.size();
  for (const Eigen::Vector3f& q : points) {
    if (!q.allFinite()) {
      ++stats.non_finite;
      continue;
    }
    splat_point(project, rays, R * q + t, range, stats);
  }
  return range;
}

std::vector<float> splat_stretches(const ViewRays& rays, const std::vector<Eigen::Vector3f>& points,
                                   const Pose& T_view_points, const Eigen::Vector3f& up, float stretch_m,
                                   DepthStats& stats) {
  const int w = rays.width;
  std::vector<float> range(rays.size(), 0.f);
  const Projector project(rays);
  const Eigen::Matrix3f R = T_view_points.linear().cast<float>();
  const Eigen::Vector3f t = T_view_points.translation().cast<float>();
  const Eigen::Vector3f down = R * (up.normalized() * -stretch_m);
  // A stretch right in front of the view may span much of it: at most this many steps.
  constexpr int kMaxSteps = 256;
  stats.points += points.size();
  for (const Eigen::Vector3f& q : points) {
    if (!q.allFinite()) {
      ++stats.non_finite;
      continue;
    }
    const Eigen::Vector3f p = R * q + t;
    const Eigen::Vector3f ends[2] = {p + down, p};
    float fu[2], fv[2];
    if (!project(ends[0], fu[0], fv[0]) || !project(ends[1], fu[1], fv[1])) {
      splat_point(project, rays, p, range, stats);  // an end outside the image: the point alone
      continue;
    }
    const float r0 = ends[0].norm(), r1 = ends[1].norm();
    const int steps =
        std::min(kMaxSteps, static_cast<int>(std::ceil(std::max(std::abs(fu[1] - fu[0]), std::abs(fv[1] - fv[0])))));
    for (int s = 0; s <= steps; ++s) {
      const float a = steps > 0 ? float(s) / float(steps) : 0.5f;
      const int u = static_cast<int>(fu[0] + a * (fu[1] - fu[0]) + 0.5f);
      const int v = static_cast<int>(fv[0] + a * (fv[1] - fv[0]) + 0.5f);
      const size_t i = size_t(v) * w + u;
      if (rays.valid[i]) keep_nearest(range, i, r0 + a * (r1 - r0), stats);
    }
  }
  return range;
}

}  // namespace omniview
