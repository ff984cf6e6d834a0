#include "core/cloud/colourer.h"

#include "core/cloud/colourer_internal.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include <opencv2/core/utility.hpp>

#include "core/map/usable_region.h"

namespace omniview {

namespace {

constexpr float kFar = std::numeric_limits<float>::max();

using Affine3f = Eigen::Matrix<float, 3, 4>;

Affine3f to_float(const Pose& T) { return T.matrix().topRows<3>().cast<float>(); }

// body(begin, end) over [0, n) in blocks, on OpenCV's threads.
template <typename Body>
void for_blocks(size_t n, const Body& body, size_t block = 16384) {
  cv::parallel_for_(cv::Range(0, static_cast<int>((n + block - 1) / block)), [&](const cv::Range& blocks) {
    body(static_cast<size_t>(blocks.start) * block, std::min(n, static_cast<size_t>(blocks.end) * block));
  });
}

}  // namespace

CloudColourer::CloudColourer(std::shared_ptr<const Rig> rig) : rig_(std::move(rig)) {
  if (!rig_) throw std::invalid_argument("CloudColourer: no rig");
  if (rig_->cameras().size() >= kNoCamera) throw std::invalid_argument("CloudColourer: more than 254 cameras");
  for (const auto& cam : rig_->cameras()) {
    auto s = std::make_shared<CameraSetup>();
    s->usable = usable_region(cam);
    s->all_usable = static_cast<size_t>(cv::countNonZero(s->usable)) == s->usable.total();
    s->centre = CentreScore::of(cam);
    s->px_per_rad = cloud_internal::pixels_per_radian(cam);
    cameras_.push_back(std::move(s));
  }
}

CloudColourer::~CloudColourer() = default;

// The steps, in order: check everything before any work (a bad image throws before threads
// start), move the points to where they were at the cloud's stamp, project them into every
// camera (depth buffers for occlusion), then fuse each point's cameras.
ColourStats CloudColourer::colour(PointCloud& cloud, const CameraImages& input, const ColourOptions& options,
                                  const Trajectory* motion) {
  const Pose T_base_cloud = check_inputs(cloud, input);
  const bool sync = options.time_sync && motion && !motion->empty();
  deskew(cloud, T_base_cloud, sync ? motion : nullptr, options.motion_bin_s);
  // Outputs, once nothing can throw.
  const size_t n = cloud.size();
  if (cloud.rgb.empty()) cloud.rgb.assign(n, {0, 0, 0});
  if (cloud.flags.empty()) cloud.flags.assign(n, 0);
  cloud.camera.resize(n);  // fusion writes every point's camera, flags and stats
  project_into_cameras(cloud, input, options, T_base_cloud, sync ? motion : nullptr);
  return fuse(cloud, input, options);
}

// The cloud's fields, the images' sizes and types, the stamps and the cloud's frame; the
// rig's default frame from the cloud's.
Pose CloudColourer::check_inputs(const PointCloud& cloud, const CameraImages& input) const {
  cloud.check("cloud");
  const Rig& rig = *rig_;
  const size_t n_cams = rig.cameras().size();
  if (input.images.size() != n_cams) {
    throw std::invalid_argument("colouring: " + std::to_string(input.images.size()) + " images for " +
                                std::to_string(n_cams) + " cameras");
  }
  if (cloud.size() > std::numeric_limits<uint32_t>::max()) {
    throw std::invalid_argument("colouring: more than 2^32 points");  // points are indexed with 32 bits
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
  return *T_base_cloud;
}

// x_, y_, z_: the points where they were at the cloud's stamp. With `motion` and per-point
// times, one correction per time bin of `bin_s`; otherwise a plain copy.
void CloudColourer::deskew(const PointCloud& cloud, const Pose& T_base_cloud, const Trajectory* motion,
                           double bin_s) {
  const size_t n = cloud.size();
  x_.resize(n);
  y_.resize(n);
  z_.resize(n);
  if (motion && !cloud.time.empty()) {
    const double bin = std::max(1e-5, bin_s);
    const Pose T_cloud_base = T_base_cloud.inverse();
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
      corrections[k] = to_float(T_cloud_base * motion->relative(cloud.stamp, t) * T_base_cloud);
    }
    for_blocks(n, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        const float t = std::isfinite(cloud.time[i]) ? cloud.time[i] : t_min;
        const size_t k = static_cast<size_t>(std::clamp((double(t) - t_min) / bin, 0.0, double(bins - 1)));
        const Eigen::Vector3f p = corrections[k] * cloud.points[i].homogeneous();
        x_[i] = p.x();
        y_[i] = p.y();
        z_[i] = p.z();
      }
    });
    return;
  }
  // On this thread, not the pool: a copy bound by memory, which handed to the pool made
  // the whole colouring slower (300 k points on 2 threads: 6.2 -> 4.0 ms without it).
  for (size_t i = 0; i < n; ++i) {
    x_[i] = cloud.points[i].x();
    y_[i] = cloud.points[i].y();
    z_[i] = cloud.points[i].z();
  }
}

// Phase 1: every point projected into each camera with an image (`motion`: each camera's
// pose at its own stamp), the depth buffers splatted and what covers each cell found.
void CloudColourer::project_into_cameras(const PointCloud& cloud, const CameraImages& input,
                                         const ColourOptions& options, const Pose& T_base_cloud,
                                         const Trajectory* motion) {
  const Rig& rig = *rig_;
  const size_t n = cloud.size();
  const size_t n_cams = rig.cameras().size();
  const std::string& base = rig.default_frame();
  const bool blend = options.fusion == Fusion::kBlend;
  // Tasks are (camera x point range), as many ranges as threads, each range with a depth
  // buffer of its own, merged after: five cameras on two threads would leave one idle for a
  // third of the time if a task were a camera.
  passes_.resize(n_cams);
  const int reach = std::max(1, int(std::lround(options.occlusion_reach_deg / options.occlusion_cell_deg)));
  const size_t ranges = std::clamp<size_t>(static_cast<size_t>(cv::getNumThreads()), 1, std::max<size_t>(1, n / 4096));
  std::vector<Affine3f> T_cam_cloud(n_cams);
  for (size_t c = 0; c < n_cams; ++c) {
    CameraPass& pass = passes_[c];
    pass.active = !input.images[c].empty();
    if (!pass.active) continue;
    const Camera& cam = rig.cameras()[c];
    const CameraSetup& s = *cameras_[c];
    const auto t_cam = input.stamps.empty() ? cloud.stamp : input.stamps[c];
    const Pose motion_fix = motion ? motion->relative(t_cam, cloud.stamp) : Pose::Identity();
    T_cam_cloud[c] = to_float(rig.camera_pose(base, c).inverse() * motion_fix * T_base_cloud);
    pass.seen.resize(ranges);
    cloud_internal::size_depth_buffer(pass, cam, s.px_per_rad, options.occlusion_cell_deg, reach);
    pass.depth.resize(options.occlusion ? ranges : 0);
  }
  // A camera's last range to finish merges its depth buffers and finds what covers each
  // cell, while other tasks still run (no wait for all cameras in between).
  auto finish_camera = [&](size_t c) {
    CameraPass& pass = passes_[c];
    if (options.occlusion) {
      float* __restrict merged = pass.depth[0].data();
      for (size_t r = 1; r < ranges; ++r) {
        const float* __restrict other = pass.depth[r].data();
        for (size_t k = 0, size = pass.padded_size(); k < size; ++k) merged[k] = std::min(merged[k], other[k]);
      }
      cloud_internal::occluding_depth(pass);
    }
    CameraSetup& s = *cameras_[c];
    if (blend && s.feather_px != options.feather_px) {
      s.feather = feather_weights(rig.cameras()[c], options.feather_px);
      s.feather_px = options.feather_px;
    }
  };
  const std::unique_ptr<std::atomic<size_t>[]> ranges_left(new std::atomic<size_t>[n_cams]);
  for (size_t c = 0; c < n_cams; ++c) ranges_left[c].store(ranges, std::memory_order_relaxed);
  cv::parallel_for_(cv::Range(0, static_cast<int>(n_cams * ranges)), [&](const cv::Range& tasks) {
    for (int task = tasks.start; task < tasks.end; ++task) {
      const size_t c = static_cast<size_t>(task) / ranges, r = static_cast<size_t>(task) % ranges;
      CameraPass& pass = passes_[c];
      if (!pass.active) continue;
      const Camera& cam = rig.cameras()[c];
      const CameraSetup& s = *cameras_[c];
      float* depth = nullptr;
      if (options.occlusion) {
        pass.depth[r].assign(pass.padded_size(), kFar);
        depth = pass.depth[r].data();
      }
      // Blocks small enough that the splat reads the projections back from L1.
      constexpr size_t kBlock = 1024;
      float u[kBlock], v[kBlock], range[kBlock];
      uint8_t valid[kBlock];
      const size_t first = n * r / ranges, end = n * (r + 1) / ranges;
      cloud_internal::Seen& seen = pass.seen[r];
      seen.reserve(end - first);
      seen.size = 0;
      for (size_t b = first; b < end; b += kBlock) {
        const size_t m = std::min(kBlock, end - b);
        cloud_internal::project_camera(cam.model, T_cam_cloud[c], x_.data() + b, y_.data() + b, z_.data() + b, m,
                                       float(cam.width - 1), float(cam.height - 1), u, v, range, valid);
        if (!s.all_usable) {
          for (size_t i = 0; i < m; ++i) {
            if ((valid[i] & 1) && s.usable.at<uint8_t>(static_cast<int>(v[i] + 0.5f), static_cast<int>(u[i] + 0.5f)) == 0) {
              valid[i] &= 2;  // masked out or past the lens' field: no colour, but still a surface
            }
          }
        }
        cloud_internal::splat_and_keep(pass, b, u, v, range, valid, m, depth, seen);
      }
      // acq_rel: the last one sees every range's buffer.
      if (ranges_left[c].fetch_sub(1, std::memory_order_acq_rel) == 1) finish_camera(c);
    }
  });
}

// Phase 2, points in chunks: pick (or blend) the cameras that see each point unhidden.
ColourStats CloudColourer::fuse(PointCloud& cloud, const CameraImages& input, const ColourOptions& options) const {
  const size_t n = cloud.size();
  const bool blend = options.fusion == Fusion::kBlend;
  std::atomic<size_t> coloured{0}, occluded{0}, self_filtered{0}, unseen{0};
  for_blocks(n, [&](size_t begin, size_t end) {
    const ColourStats chunk = blend ? this->blend(cloud, input, options, begin, end)
                                    : nearest_centre(cloud, input, options, begin, end);
    coloured += chunk.coloured;
    occluded += chunk.occluded;
    self_filtered += chunk.self_filtered;
    unseen += chunk.unseen;
  }, 4096);

  ColourStats stats;
  stats.points = n;
  stats.coloured = coloured;
  stats.occluded = occluded;
  stats.self_filtered = self_filtered;
  stats.unseen = unseen;
  return stats;
}

}  // namespace omniview
