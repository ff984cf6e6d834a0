#include "core/cloud/colourer.h"

#include "core/cloud/colourer_internal.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "core/map/multiversion.h"
#include "core/map/usable_region.h"

namespace omniview {

namespace {

constexpr float kFar = std::numeric_limits<float>::max();

using Affine3f = Eigen::Matrix<float, 3, 4>;

Affine3f to_float(const Pose& T) { return T.matrix().topRows<3>().cast<float>(); }

// Projects every point with one camera's model: the variant is visited once, and this
// loop is specialised per model, so the projection inlines and GCC vectorises it.
template <typename Model>
[[gnu::always_inline]] inline void project_all(const Model& model, const Affine3f& T, const float* __restrict x,
                                               const float* __restrict y, const float* __restrict z, size_t n, float max_u,
                                               float max_v, float* __restrict u, float* __restrict v,
                                               float* __restrict range, uint8_t* __restrict ok) {
  const float r00 = T(0, 0), r01 = T(0, 1), r02 = T(0, 2), t0 = T(0, 3);
  const float r10 = T(1, 0), r11 = T(1, 1), r12 = T(1, 2), t1 = T(1, 3);
  const float r20 = T(2, 0), r21 = T(2, 1), r22 = T(2, 2), t2 = T(2, 3);
  for (size_t i = 0; i < n; ++i) {
    const float xc = r00 * x[i] + r01 * y[i] + r02 * z[i] + t0;
    const float yc = r10 * x[i] + r11 * y[i] + r12 * z[i] + t1;
    const float zc = r20 * x[i] + r21 * y[i] + r22 * z[i] + t2;
    float uu, vv;
    const bool good = model.project(xc, yc, zc, uu, vv);
    u[i] = uu;
    v[i] = vv;
    range[i] = std::sqrt(xc * xc + yc * yc + zc * zc);
    // Bit 1: the model images it (for the depth buffer, which reaches past the image's
    // edges); bit 0: also inside the image. NaN coordinates fail every comparison, so
    // points without a return drop out here.
    const bool inside = good & (uu >= 0.f) & (vv >= 0.f) & (uu <= max_u) & (vv <= max_v);
    ok[i] = static_cast<uint8_t>((static_cast<uint8_t>(good) << 1) | static_cast<uint8_t>(inside));
  }
}

// One camera's projections, compiled for baseline x86-64 and for AVX2 (picked at load).
OMNIVIEW_MULTIVERSION
void project_camera(const CameraModel& camera_model, const Affine3f& T, const float* x, const float* y, const float* z, size_t n,
                    float max_u, float max_v, float* u, float* v, float* range, uint8_t* ok) {
  // get_if rather than std::visit: the loop must inline into each clone of this function.
  auto run = [&](const auto* model) {
    if (model) project_all(*model, T, x, y, z, n, max_u, max_v, u, v, range, ok);
  };
  run(std::get_if<PinholeRadtan>(&camera_model));
  run(std::get_if<Equidistant>(&camera_model));
  run(std::get_if<Fov>(&camera_model));
  run(std::get_if<OmniRadtan>(&camera_model));
  run(std::get_if<DoubleSphere>(&camera_model));
  run(std::get_if<Eucm>(&camera_model));
}

// The depth of a surface in front of each cell, from the cloud's own points splatted into
// `depth` (nearest per cell): a cell is covered when nearer samples lie on both sides of it
// within `reach` cells, vertically or horizontally (the gap between two of a lidar's rings
// on a near surface). Requiring both sides, and leaving the cell itself out, keeps a
// surface seen at a grazing angle from hiding itself: there the nearer ring lies on one
// side only, or shares the cell.
void occluding_depth(const cv::Mat& depth, int reach, cv::Mat& up, cv::Mat& down, cv::Mat& left, cv::Mat& right,
                     cv::Mat& out) {
  const cv::Scalar far(kFar);
  const int rows = depth.rows, cols = depth.cols;
  cv::Mat window;
  // Windows that end (or start) at the cell, then moved one cell on so the cell is out.
  auto shifted = [&](const cv::Mat& kernel, cv::Point anchor, int dy, int dx, cv::Mat& dst) {
    cv::erode(depth, window, kernel, anchor, 1, cv::BORDER_CONSTANT, far);
    dst.create(rows, cols, CV_32F);
    dst.setTo(far);
    const cv::Rect from(std::max(0, -dx), std::max(0, -dy), cols - std::abs(dx), rows - std::abs(dy));
    const cv::Rect to(std::max(0, dx), std::max(0, dy), from.width, from.height);
    window(from).copyTo(dst(to));
  };
  const cv::Mat column = cv::Mat::ones(reach, 1, CV_8U), row = cv::Mat::ones(1, reach, CV_8U);
  shifted(column, cv::Point(0, reach - 1), 1, 0, up);     // rows y-reach .. y-1
  shifted(column, cv::Point(0, 0), -1, 0, down);          // rows y+1 .. y+reach
  shifted(row, cv::Point(reach - 1, 0), 0, 1, left);      // columns x-reach .. x-1
  shifted(row, cv::Point(0, 0), 0, -1, right);            // columns x+1 .. x+reach
  cv::max(up, down, up);
  cv::max(left, right, left);
  cv::min(up, left, out);
}

}  // namespace

CloudColourer::CloudColourer(std::shared_ptr<const Rig> rig) : rig_(std::move(rig)) {
  if (!rig_) throw std::invalid_argument("CloudColourer: no rig");
  if (rig_->cameras().size() >= kNoCamera) throw std::invalid_argument("CloudColourer: more than 254 cameras");
  for (const auto& cam : rig_->cameras()) {
    auto s = std::make_shared<CameraSetup>();
    s->usable = usable_region(cam);
    s->all_usable = static_cast<size_t>(cv::countNonZero(s->usable)) == s->usable.total();
    s->cx = static_cast<float>((cam.width - 1) / 2.0);
    s->cy = static_cast<float>((cam.height - 1) / 2.0);
    s->inv_half_diag2 = 4.0f / static_cast<float>(cam.width * cam.width + cam.height * cam.height);
    // Pixels per radian near the image centre, from two neighbouring rays.
    Eigen::Vector3d a, b;
    if (unproject(cam.model, Eigen::Vector2d(s->cx, s->cy), a) && unproject(cam.model, Eigen::Vector2d(s->cx + 1, s->cy), b)) {
      const double angle = std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
      if (angle > 0) s->px_per_rad = 1.0 / angle;
    } else {
      s->px_per_rad = cam.width / M_PI;
    }
    cameras_.push_back(std::move(s));
  }
}

CloudColourer::~CloudColourer() = default;

ColourStats CloudColourer::colour(PointCloud& cloud, const CameraImages& input, const ColourOptions& options,
                                  const Trajectory* motion) {
  cloud.check("cloud");
  const Rig& rig = *rig_;
  const size_t n = cloud.size();
  const size_t n_cams = rig.cameras().size();
  if (input.images.size() != n_cams) {
    throw std::invalid_argument("colouring: " + std::to_string(input.images.size()) + " images for " +
                                std::to_string(n_cams) + " cameras");
  }
  if (!input.stamps.empty() && input.stamps.size() != n_cams) {
    throw std::invalid_argument("colouring: image stamps must be none or one per camera");
  }
  const std::string& base = rig.default_frame();
  const std::string cloud_frame = cloud.frame.empty() ? base : cloud.frame;
  const auto T_base_cloud = rig.frames().try_lookup(base, cloud_frame);
  if (!T_base_cloud) {
    throw std::invalid_argument("colouring: the cloud's frame '" + cloud_frame + "' is not connected to the rig's frame '" +
                                base + "'");
  }
  const bool sync = options.time_sync && motion && !motion->empty();

  // The points where they were at the cloud's stamp (per-point times: one correction per bin).
  x_.resize(n);
  y_.resize(n);
  z_.resize(n);
  if (sync && !cloud.time.empty()) {
    const double bin = std::max(1e-5, options.motion_bin_s);
    const Pose T_cloud_base = T_base_cloud->inverse();
    float t_min = std::numeric_limits<float>::max(), t_max = std::numeric_limits<float>::lowest();
    for (float t : cloud.time) {
      if (std::isfinite(t)) {
        t_min = std::min(t_min, t);
        t_max = std::max(t_max, t);
      }
    }
    if (t_min > t_max) t_min = t_max = 0;
    // At most 100 k corrections (200 s of 2 ms bins); clamped in double, before converting.
    const double span_bins = (double(t_max) - t_min) / bin;
    const size_t bins = span_bins >= 99999 ? 100000 : static_cast<size_t>(span_bins) + 1;
    std::vector<Affine3f> corrections(bins);
    for (size_t k = 0; k < bins; ++k) {
      const auto t = cloud.stamp + std::chrono::duration_cast<std::chrono::system_clock::duration>(
                                       std::chrono::duration<double>(t_min + (k + 0.5) * bin));
      corrections[k] = to_float(T_cloud_base * motion->relative(cloud.stamp, t) * *T_base_cloud);
    }
    for (size_t i = 0; i < n; ++i) {
      const float t = std::isfinite(cloud.time[i]) ? cloud.time[i] : t_min;
      const size_t k = static_cast<size_t>(std::clamp((double(t) - t_min) / bin, 0.0, double(bins - 1)));
      const Eigen::Vector3f p = corrections[k] * cloud.points[i].homogeneous();
      x_[i] = p.x();
      y_[i] = p.y();
      z_[i] = p.z();
    }
  } else {
    for (size_t i = 0; i < n; ++i) {
      x_[i] = cloud.points[i].x();
      y_[i] = cloud.points[i].y();
      z_[i] = cloud.points[i].z();
    }
  }

  // Outputs.
  if (cloud.rgb.empty()) cloud.rgb.assign(n, {0, 0, 0});
  if (cloud.flags.empty()) cloud.flags.assign(n, 0);
  cloud.camera.assign(n, kNoCamera);
  for (auto& f : cloud.flags) f &= static_cast<uint8_t>(~(cloud_flags::kColoured | cloud_flags::kOccluded));
  const bool blend = options.fusion == Fusion::kBlend;

  // Checks before any work, so that a bad image throws before threads start.
  for (size_t c = 0; c < n_cams; ++c) {
    const cv::Mat& image = input.images[c];
    const Camera& cam = rig.cameras()[c];
    if (!image.empty() &&
        (image.cols != cam.width || image.rows != cam.height || (image.type() != CV_8UC1 && image.type() != CV_8UC3))) {
      throw std::invalid_argument("colouring: camera '" + cam.name + "' image is " + std::to_string(image.cols) + "x" +
                                  std::to_string(image.rows) + " (type " + std::to_string(image.type()) +
                                  "); its calibration is for " + std::to_string(cam.width) + "x" +
                                  std::to_string(cam.height) + " 8-bit grey or BGR");
    }
  }

  // Phase 1, one camera per task: project every point, splat the depth buffer and find
  // what covers each cell.
  passes_.resize(n_cams);
  cv::parallel_for_(cv::Range(0, static_cast<int>(n_cams)), [&](const cv::Range& range) {
    for (int ci = range.start; ci < range.end; ++ci) {
      const size_t c = static_cast<size_t>(ci);
      CameraPass& pass = passes_[c];
      pass.active = !input.images[c].empty();
      if (!pass.active) continue;
      const Camera& cam = rig.cameras()[c];
      CameraSetup& s = *cameras_[c];
      const auto t_cam = input.stamps.empty() ? cloud.stamp : input.stamps[c];
      const Pose motion_fix = sync ? motion->relative(t_cam, cloud.stamp) : Pose::Identity();
      const Affine3f T_cam_cloud = to_float(rig.camera_pose(base, c).inverse() * motion_fix * *T_base_cloud);
      pass.u.resize(n);
      pass.v.resize(n);
      pass.range.resize(n);
      pass.valid.resize(n);
      project_camera(cam.model, T_cam_cloud, x_.data(), y_.data(), z_.data(), n, float(cam.width - 1), float(cam.height - 1),
                     pass.u.data(), pass.v.data(), pass.range.data(), pass.valid.data());
      const float cell = std::max(1.0f, float(s.px_per_rad * options.occlusion_cell_deg * M_PI / 180));
      pass.inv_cell = 1.f / cell;
      // The buffer reaches `reach` cells past the image on every side, so that a surface just
      // outside the picture still covers what lies behind it at the picture's edge.
      const int reach = std::max(1, int(std::lround(options.occlusion_reach_deg / options.occlusion_cell_deg)));
      pass.offset = static_cast<float>(reach);
      if (options.occlusion) {
        pass.depth.create(static_cast<int>(cam.height * pass.inv_cell) + 1 + 2 * reach,
                          static_cast<int>(cam.width * pass.inv_cell) + 1 + 2 * reach, CV_32F);
        pass.depth.setTo(kFar);
      }
      const float cols = static_cast<float>(pass.depth.cols), rows = static_cast<float>(pass.depth.rows);
      uint8_t* valid = pass.valid.data();
      const float* u = pass.u.data();
      const float* v = pass.v.data();
      for (size_t i = 0; i < n; ++i) {
        if (!valid[i]) continue;
        if (!s.all_usable && (valid[i] & 1) &&
            s.usable.at<uint8_t>(static_cast<int>(v[i] + 0.5f), static_cast<int>(u[i] + 0.5f)) == 0) {
          valid[i] &= 2;  // masked out or past the lens' field: no colour, but still a surface
        }
        if (options.occlusion) {
          const float cx = u[i] * pass.inv_cell + pass.offset, cy = v[i] * pass.inv_cell + pass.offset;
          if (cx >= 0.f && cy >= 0.f && cx < cols && cy < rows) {
            float& d = pass.depth.at<float>(static_cast<int>(cy), static_cast<int>(cx));
            d = std::min(d, pass.range[i]);
          }
        }
      }
      if (options.occlusion) occluding_depth(pass.depth, reach, pass.up, pass.down, pass.left, pass.right, pass.occluder);
      if (blend && s.feather_px != options.feather_px) {
        s.feather = feather_weights(cam, options.feather_px);
        s.feather_px = options.feather_px;
      }
    }
  });

  // Phase 2, points in chunks: pick (or blend) the cameras that see each point unhidden.
  const float rel = 1.f + options.occlusion_tolerance_rel, abs_tol = options.occlusion_tolerance_m;
  cv::parallel_for_(cv::Range(0, static_cast<int>((n + 4095) / 4096)), [&](const cv::Range& chunks) {
    const size_t begin = static_cast<size_t>(chunks.start) * 4096, end = std::min(n, static_cast<size_t>(chunks.end) * 4096);
    if (!blend) {
      nearest_centre(cloud, input, options, begin, end);
      return;
    }
    for (size_t i = begin; i < end; ++i) {
      uint8_t& flags = cloud.flags[i];
      if (flags & cloud_flags::kSelf) continue;
      bool hidden = false;
      uint8_t best_cam = kNoCamera;
      float best = std::numeric_limits<float>::max(), best_u = 0, best_v = 0;
      float sum_w = 0, sum[3] = {0, 0, 0};
      for (size_t c = 0; c < n_cams; ++c) {
        const CameraPass& pass = passes_[c];
        if (!pass.active || !(pass.valid[i] & 1)) continue;
        const float u = pass.u[i], v = pass.v[i];
        if (options.occlusion) {
          const float nearest = pass.occluder.at<float>(static_cast<int>(v * pass.inv_cell + pass.offset),
                                                        static_cast<int>(u * pass.inv_cell + pass.offset));
          if (pass.range[i] > nearest * rel + abs_tol) {
            hidden = true;
            continue;
          }
        }
        const CameraSetup& s = *cameras_[c];
        if (blend) {
          const float w = s.feather.at<float>(static_cast<int>(v + 0.5f), static_cast<int>(u + 0.5f));
          if (w <= 0) continue;
          float rgb[3];
          cloud_internal::sample(input.images[c], u, v, rgb);
          sum_w += w;
          for (int k = 0; k < 3; ++k) sum[k] += w * rgb[k];
          if (-w < best) {  // blending: `best` holds minus the heaviest weight
            best = -w;
            best_cam = static_cast<uint8_t>(c);
          }
        } else {
          const float du = u - s.cx, dv = v - s.cy;
          const float score = (du * du + dv * dv) * s.inv_half_diag2;
          if (score < best) {
            best = score;
            best_cam = static_cast<uint8_t>(c);
            best_u = u;
            best_v = v;
          }
        }
      }
      if (best_cam == kNoCamera) {
        if (hidden) flags |= cloud_flags::kOccluded;
        continue;
      }
      float rgb[3];
      if (blend) {
        for (int k = 0; k < 3; ++k) rgb[k] = sum[k] / sum_w;
      } else {
        cloud_internal::sample(input.images[best_cam], best_u, best_v, rgb);
      }
      cloud.rgb[i] = {cloud_internal::to_byte(rgb[0]), cloud_internal::to_byte(rgb[1]), cloud_internal::to_byte(rgb[2])};
      cloud.camera[i] = best_cam;
      flags |= cloud_flags::kColoured;
    }
  });

  ColourStats stats;
  stats.points = n;
  for (const uint8_t f : cloud.flags) {
    if (f & cloud_flags::kSelf) {
      ++stats.self_filtered;
    } else if (f & cloud_flags::kColoured) {
      ++stats.coloured;
    } else if (f & cloud_flags::kOccluded) {
      ++stats.occluded;
    } else {
      ++stats.unseen;
    }
  }
  return stats;
}

}  // namespace omniview
