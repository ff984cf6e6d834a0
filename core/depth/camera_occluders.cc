#include "core/depth/camera_occluders.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/core/utility.hpp>

#include "core/cloud/colourer_internal.h"
#include "core/depth/gap_fill.h"
#include "core/map/parallel_rows.h"

namespace omniview {

CameraRangeImages::CameraRangeImages(const Rig& rig, double cell_deg) : rig_(rig) {
  for (const Camera& cam : rig.cameras()) {
    // The colourer's buffer layout without its margin (gap filling needs no samples past
    // the image).
    cloud_internal::CameraPass pass;
    cloud_internal::size_depth_buffer(pass, cam, cloud_internal::pixels_per_radian(cam), cell_deg, 0);
    Grid g;
    g.inv_cell = pass.inv_cell;
    const float cell = 1.f / pass.inv_cell;
    ViewRays& rays = g.rays;  // one ray per cell, for gap filling
    rays.width = pass.cols;
    rays.height = pass.rows;
    rays.pixel_rad = cell_deg * M_PI / 180;
    const size_t cells = size_t(pass.rows) * size_t(pass.cols);
    rays.x.resize(cells);
    rays.y.resize(cells);
    rays.z.resize(cells);
    rays.valid.resize(cells);
    for (int r = 0; r < pass.rows; ++r) {
      for (int k = 0; k < pass.cols; ++k) {
        Eigen::Vector3d ray;
        const size_t i = size_t(r) * pass.cols + k;
        rays.valid[i] = unproject(cam.model, Eigen::Vector2d((k + 0.5) * cell - 0.5, (r + 0.5) * cell - 0.5), ray) &&
                        ray.norm() > 0;
        const Eigen::Vector3d unit = rays.valid[i] ? Eigen::Vector3d(ray.normalized()) : Eigen::Vector3d::Zero();
        rays.x[i] = float(unit.x()), rays.y[i] = float(unit.y()), rays.z[i] = float(unit.z());
      }
    }
    grids_.push_back(std::move(g));
  }
}

Occlusion CameraRangeImages::occluders(const std::vector<Eigen::Vector3f>& points, const std::string& points_frame,
                                       const Pose& T_frame_points, const DepthOptions& depth, float tolerance_rel,
                                       float tolerance_m, const std::vector<Eigen::Vector3f>* completion) const {
  const auto& cameras = rig_.cameras();
  for (const auto& cam : cameras) {
    if (!rig_.frames().try_lookup(points_frame, cam.name)) {
      throw std::invalid_argument("occlusion: the points' frame '" + points_frame + "' is not connected to camera '" +
                                  cam.name + "'");
    }
  }
  Occlusion occlusion;
  occlusion.tolerance_rel = tolerance_rel;
  occlusion.tolerance_m = tolerance_m;
  occlusion.cameras.resize(cameras.size());
  // Structure of arrays for project_camera.
  struct Coordinates {
    std::vector<float> x, y, z;
    explicit Coordinates(const std::vector<Eigen::Vector3f>& points)
        : x(points.size()), y(points.size()), z(points.size()) {
      for (size_t i = 0; i < points.size(); ++i) x[i] = points[i].x(), y[i] = points[i].y(), z[i] = points[i].z();
    }
  };
  const Coordinates measured(points);
  // The completing points as the view takes them (splat_stretches): vertical stretches of
  // DepthOptions::completion_stretch_m down from each, here from end to end.
  std::vector<Eigen::Vector3f> lower, upper;
  if (completion) {
    const Eigen::Vector3f down(0, 0, -depth.completion_stretch_m);
    lower.reserve(completion->size()), upper.reserve(completion->size());
    for (const auto& p : *completion) lower.push_back(p + down), upper.push_back(p);
  }
  const Coordinates completing_lower(lower), completing_upper(upper);
  parallel_rows(cv::Range(0, static_cast<int>(cameras.size())), [&](const cv::Range& range) {
    for (int c = range.start; c < range.end; ++c) {
      const Camera& cam = cameras[c];
      const Grid& g = grids_[c];
      const int rows = g.rays.height, cols = g.rays.width;
      const size_t cells = g.rays.size();
      const Eigen::Matrix<float, 3, 4> T =
          (rig_.camera_pose(points_frame, c).inverse() * T_frame_points).matrix().topRows<3>().cast<float>();
      // Splat: nearest range per cell, of the measured and the completing points alike.
      std::vector<float> range_image(cells, 0.f);
      const auto splat = [&](const Coordinates& p) {
        constexpr size_t kBlock = 1024;
        float u[kBlock], v[kBlock], rr[kBlock];
        uint8_t valid[kBlock];
        const size_t n = p.x.size();
        for (size_t b = 0; b < n; b += kBlock) {
          const size_t m = std::min(kBlock, n - b);
          cloud_internal::project_camera(cam.model, T, p.x.data() + b, p.y.data() + b, p.z.data() + b, m,
                                         float(cam.width - 1), float(cam.height - 1), u, v, rr, valid);
          for (size_t i = 0; i < m; ++i) {
            if (!(valid[i] & 1)) continue;
            const size_t k = size_t(static_cast<int>(v[i] * g.inv_cell)) * cols + static_cast<int>(u[i] * g.inv_cell);
            if (range_image[k] == 0.f || rr[i] < range_image[k]) range_image[k] = rr[i];
          }
        }
      };
      splat(measured);
      // Each stretch drawn cell by cell between its ends (an end outside the image: the
      // other alone).
      {
        constexpr size_t kBlock = 1024;
        float u0[kBlock], v0[kBlock], r0[kBlock], u1[kBlock], v1[kBlock], r1[kBlock];
        uint8_t ok0[kBlock], ok1[kBlock];
        const size_t n = completing_lower.x.size();
        const auto keep = [&](float u, float v, float r) {
          const size_t k = size_t(static_cast<int>(v * g.inv_cell)) * cols + static_cast<int>(u * g.inv_cell);
          if (range_image[k] == 0.f || r < range_image[k]) range_image[k] = r;
        };
        for (size_t b = 0; b < n; b += kBlock) {
          const size_t m = std::min(kBlock, n - b);
          const float max_u = float(cam.width - 1), max_v = float(cam.height - 1);
          cloud_internal::project_camera(cam.model, T, completing_lower.x.data() + b, completing_lower.y.data() + b,
                                         completing_lower.z.data() + b, m, max_u, max_v, u0, v0, r0, ok0);
          cloud_internal::project_camera(cam.model, T, completing_upper.x.data() + b, completing_upper.y.data() + b,
                                         completing_upper.z.data() + b, m, max_u, max_v, u1, v1, r1, ok1);
          for (size_t i = 0; i < m; ++i) {
            const bool lower_in = ok0[i] & 1, upper_in = ok1[i] & 1;
            if (!lower_in || !upper_in) {
              if (lower_in) keep(u0[i], v0[i], r0[i]);
              if (upper_in) keep(u1[i], v1[i], r1[i]);
              continue;
            }
            const float du = (u1[i] - u0[i]) * g.inv_cell, dv = (v1[i] - v0[i]) * g.inv_cell;
            const int steps = std::min(256, static_cast<int>(std::ceil(std::max(std::abs(du), std::abs(dv)))));
            for (int s = 0; s <= steps; ++s) {
              const float t = steps > 0 ? float(s) / float(steps) : 0.5f;
              keep(u0[i] + t * (u1[i] - u0[i]), v0[i] + t * (v1[i] - v0[i]), r0[i] + t * (r1[i] - r0[i]));
            }
          }
        }
      }
      DepthStats ignored;
      const std::vector<float> filled = fill_gaps(g.rays, range_image, depth, ignored);
      // A cell covers what lies behind it only where its neighbours are as near: at an
      // object's silhouette a cell holds both the object and what is beside it, and the
      // z-buffer's nearest would blacken the visible side along every edge.
      const float far = std::numeric_limits<float>::max();
      std::vector<float> cover(cells, far);
      for (int r = 1; r + 1 < rows; ++r) {
        for (int k = 1; k + 1 < cols; ++k) {
          float m = 0.f;
          for (int dr = -1; dr <= 1; ++dr) {
            for (int dk = -1; dk <= 1; ++dk) {
              const float f = filled[size_t(r + dr) * cols + (k + dk)];
              m = std::max(m, f > 0.f ? f : far);
            }
          }
          cover[size_t(r) * cols + k] = m;
        }
      }
      CameraOccluder& out = occlusion.cameras[c];
      out.assign_row_major(cover, rows, cols);
      out.inv_cell = g.inv_cell;
      out.offset = 0;
    }
  });
  return occlusion;
}

Occlusion points_occlusion(const CameraRangeImages& cameras, const std::vector<Eigen::Vector3f>& points,
                           const std::string& frame, const Pose& T_frame_points, const ViewOcclusionOptions& options,
                           const std::vector<Eigen::Vector3f>* completion) {
  return cameras.occluders(points, frame, T_frame_points, options.fill, options.tolerance_rel, options.tolerance_m,
                           completion);
}

Occlusion for_view(const Occlusion& occluders, const MeasuredDepthView& view) {
  Occlusion occlusion = occluders;
  occlusion.judged = view.occlusion_judged();
  return occlusion;
}

Occlusion view_occlusion(const CameraRangeImages& cameras, const MeasuredDepthView& view,
                         const std::vector<Eigen::Vector3f>& points, const Pose& T_view_points,
                         const ViewOcclusionOptions& options, const std::vector<Eigen::Vector3f>* completion) {
  const ViewSpec& spec = view.spec();
  const std::string frame = spec.frame.empty() ? cameras.rig().default_frame() : spec.frame;
  // The measured points alone: the view's surface between them is its own gap fill, and
  // each camera fills its range image by the same rule in its own geometry. (The view's
  // filled surface was added here once: where it bridged an object's top and the floor in a
  // bird's-eye view it stood as a wall in the cameras' way and blackened floor they see:
  // golden bird's-eye on one VLP-16 rotation 29.9 -> 31.0 dB without it, on depth images
  // 26.2 -> 27.8 dB, the unseen pixels painted within 1 %. Without it the occluders are the
  // same for every view of the points, and the daemon makes them once per geometry.)
  return for_view(points_occlusion(cameras, points, frame, spec.T_frame_view() * T_view_points, options, completion),
                  view);
}

}  // namespace omniview
