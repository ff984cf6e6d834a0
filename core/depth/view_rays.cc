#include "core/depth/view_rays.h"

#include <algorithm>
#include <cmath>

#include <opencv2/core/utility.hpp>

#include "core/map/parallel_rows.h"

namespace omniview {

std::shared_ptr<const ViewRays> make_view_rays(std::shared_ptr<const View> view) {
  auto rays = std::make_shared<ViewRays>();
  const int w = view->width(), h = view->height();
  const size_t n = size_t(w) * size_t(h);
  rays->width = w;
  rays->height = h;
  rays->x.resize(n);
  rays->y.resize(n);
  rays->z.resize(n);
  rays->valid.resize(n);
  rays->fixed_range.resize(n);
  rays->fixed_on_ground.resize(n);
  const ViewSpec& spec = view->spec();
  const Pose T = spec.T_frame_view();
  const Vec3 down = T.linear().transpose() * Vec3(0, 0, -1);  // the frame's -z in the view frame
  const double height = T.translation().z() - spec.ground_z;
  const bool has_ground = spec.ground || spec.type == ViewType::kBirdseye;
  parallel_rows(cv::Range(0, h), [&](const cv::Range& rows) {
    std::vector<float> px(w), py(w), pz(w);
    std::vector<uint8_t> on_surface(w);
    for (int v = rows.start; v < rows.end; ++v) {
      view->row_points(v, px.data(), py.data(), pz.data(), on_surface.data());
      for (int u = 0; u < w; ++u) {
        const size_t i = size_t(v) * w + u;
        Vec3 dir;
        const bool has_ray = view->pixel_to_direction(u, v, dir) && dir.norm() > 0;
        const Vec3 unit = has_ray ? Vec3(dir.normalized()) : Vec3::Zero();
        rays->x[i] = static_cast<float>(unit.x());
        rays->y[i] = static_cast<float>(unit.y());
        rays->z[i] = static_cast<float>(unit.z());
        rays->valid[i] = has_ray;
        rays->fixed_range[i] = has_ray && on_surface[u] ? std::hypot(px[u], py[u], pz[u]) : 0.f;
        const double descent = unit.dot(down);
        rays->fixed_on_ground[i] = has_ground && rays->fixed_range[i] > 0.f && descent > 1e-9 &&
                                   rays->fixed_range[i] >= 0.999 * height / descent;
      }
    }
  });
  // The angle between the two rays around the image centre (both exist for every type).
  Vec3 a, b;
  const double cu = (w - 1) / 2.0, cv = (h - 1) / 2.0;
  if (view->pixel_to_direction(cu - 0.5, cv, a) && view->pixel_to_direction(cu + 0.5, cv, b)) {
    rays->pixel_rad = std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
  }
  if (!(rays->pixel_rad > 0)) rays->pixel_rad = M_PI / std::max(w, 1);
  rays->view = std::move(view);
  return rays;
}

}  // namespace omniview
