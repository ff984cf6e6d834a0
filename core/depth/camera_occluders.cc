#include "core/depth/camera_occluders.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/core/utility.hpp>

#include "core/cloud/colourer_internal.h"

namespace omniview {

Occlusion camera_occluders(const Rig& rig, const std::vector<Eigen::Vector3f>& points, const std::string& points_frame,
                           const ColourOptions& options, const Pose& T_frame_points) {
  const auto& cameras = rig.cameras();
  Occlusion occlusion;
  occlusion.tolerance_rel = options.occlusion_tolerance_rel;
  occlusion.tolerance_m = options.occlusion_tolerance_m;
  occlusion.cameras.resize(cameras.size());
  if (!options.occlusion) return occlusion;
  for (const auto& cam : cameras) {
    if (!rig.frames().try_lookup(points_frame, cam.name)) {
      throw std::invalid_argument("occlusion: the points' frame '" + points_frame + "' is not connected to camera '" +
                                  cam.name + "'");
    }
  }
  // The points as arrays, as the colourer's projection reads them (NaN drops out there).
  const size_t n = points.size();
  std::vector<float> x(n), y(n), z(n);
  for (size_t i = 0; i < n; ++i) x[i] = points[i].x(), y[i] = points[i].y(), z[i] = points[i].z();
  const int reach = std::max(1, int(std::lround(options.occlusion_reach_deg / options.occlusion_cell_deg)));
  cv::parallel_for_(cv::Range(0, static_cast<int>(cameras.size())), [&](const cv::Range& range) {
    for (int c = range.start; c < range.end; ++c) {
      const Camera& cam = cameras[c];
      cloud_internal::CameraPass pass;
      cloud_internal::size_depth_buffer(pass, cam, cloud_internal::pixels_per_radian(cam), options.occlusion_cell_deg,
                                        reach);
      pass.depth.assign(1, std::vector<float>(pass.padded_size(), std::numeric_limits<float>::max()));
      const Eigen::Matrix<float, 3, 4> T =
          (rig.camera_pose(points_frame, c).inverse() * T_frame_points).matrix().topRows<3>().cast<float>();
      constexpr size_t kBlock = 1024;
      float u[kBlock], v[kBlock], r[kBlock];
      uint8_t valid[kBlock];
      cloud_internal::Seen seen;  // the points this camera would colour: not needed here
      seen.reserve(kBlock);
      for (size_t b = 0; b < n; b += kBlock) {
        const size_t m = std::min(kBlock, n - b);
        cloud_internal::project_camera(cam.model, T, x.data() + b, y.data() + b, z.data() + b, m,
                                       float(cam.width - 1), float(cam.height - 1), u, v, r, valid);
        seen.size = 0;
        cloud_internal::splat_and_keep(pass, b, u, v, r, valid, m, pass.depth[0].data(), seen);
      }
      cloud_internal::occluding_depth(pass);
      CameraOccluder& out = occlusion.cameras[c];
      out.assign_row_major(pass.occluder, pass.rows, pass.cols);
      out.inv_cell = pass.inv_cell;
      out.offset = pass.offset;
    }
  });
  return occlusion;
}

}  // namespace omniview

namespace omniview {

ColourOptions view_occlusion_options() {
  ColourOptions o;
  o.occlusion_cell_deg = 0.2;
  o.occlusion_reach_deg = 0.4;
  return o;
}

Occlusion view_occlusion(const Rig& rig, const MeasuredDepthView& view, const std::vector<Eigen::Vector3f>& points,
                         const Pose& T_view_points, const ColourOptions& options, int surface_step) {
  const ViewSpec& spec = view.spec();
  const std::string frame = spec.frame.empty() ? rig.default_frame() : spec.frame;
  std::vector<Eigen::Vector3f> all;
  all.reserve(points.size() + view.width() * view.height() / (surface_step * surface_step));
  const Eigen::Matrix3f R = T_view_points.linear().cast<float>();
  const Eigen::Vector3f t = T_view_points.translation().cast<float>();
  for (const auto& p : points) all.push_back(R * p + t);  // NaN stays NaN and drops out
  const int step = std::max(1, surface_step);
  for (int v = 0; v < view.height(); v += step) {
    for (int u = 0; u < view.width(); u += step) {
      if (view.measured_at(u, v) != 255) continue;
      Vec3 p;
      if (view.pixel_to_point(u, v, p)) all.push_back(p.cast<float>());
    }
  }
  Occlusion occlusion = camera_occluders(rig, all, frame, options, spec.T_frame_view());
  occlusion.judged = view.occlusion_judged();
  return occlusion;
}

}  // namespace omniview
