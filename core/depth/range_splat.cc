#include "core/depth/range_splat.h"

#include <cmath>

namespace omniview {
namespace {

// A pinhole view's projection in float, inlined: the generic View::point_to_pixel costs a
// virtual call and double arithmetic per point, a third of a 300 k-point update.
struct PinholeProjection {
  float f, cx, cy, max_u, max_v;
  bool operator()(float x, float y, float z, int& u, int& v) const {
    if (!(x > 1e-6f)) return false;
    const float inv = f / x;
    const float fu = cx - y * inv, fv = cy - z * inv;
    if (!(fu >= -0.5f && fv >= -0.5f && fu < max_u && fv < max_v)) return false;  // NaN fails too
    u = static_cast<int>(fu + 0.5f);
    v = static_cast<int>(fv + 0.5f);
    return true;
  }
};

}  // namespace

std::vector<float> splat_points(const ViewRays& rays, const std::vector<Eigen::Vector3f>& points,
                                const Pose& T_view_points, DepthStats& stats) {
  const int w = rays.width, h = rays.height;
  std::vector<float> range(rays.size(), 0.f);
  const View& view = *rays.view;
  const ViewSpec& spec = view.spec();
  const bool pinhole = spec.type == ViewType::kPerspective || spec.type == ViewType::kBirdseye;
  const float f = static_cast<float>((spec.width / 2.0) / std::tan(spec.hfov_deg * M_PI / 360.0));
  const PinholeProjection project{f, static_cast<float>((spec.width - 1) / 2.0),
                                  static_cast<float>((spec.height - 1) / 2.0), w - 0.5f, h - 0.5f};
  const Eigen::Matrix3f R = T_view_points.linear().cast<float>();
  const Eigen::Vector3f t = T_view_points.translation().cast<float>();
  stats.points += points.size();
  for (const Eigen::Vector3f& q : points) {
    if (!q.allFinite()) {
      ++stats.non_finite;
      continue;
    }
    const Eigen::Vector3f p = R * q + t;
    int u = 0, v = 0;
    bool inside = false;
    if (pinhole) {
      inside = project(p.x(), p.y(), p.z(), u, v);
    } else {
      Vec2 uv;
      inside = view.point_to_pixel(p.cast<double>(), uv);
      u = static_cast<int>(std::lround(uv.x()));
      v = static_cast<int>(std::lround(uv.y()));
      inside = inside && u >= 0 && v >= 0 && u < w && v < h;
    }
    const size_t i = size_t(v) * w + u;
    if (!inside || !rays.valid[i]) {
      ++stats.outside_view;
      continue;
    }
    const float r = p.norm();
    if (!(r > 0)) {
      ++stats.outside_view;
      continue;
    }
    float& cell = range[i];
    if (cell == 0.f) ++stats.splatted_pixels;
    if (cell == 0.f || r < cell) cell = r;
  }
  return range;
}

}  // namespace omniview
