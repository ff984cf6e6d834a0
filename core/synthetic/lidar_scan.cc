#include "core/synthetic/lidar_scan.h"

#include <cmath>

#include <opencv2/core.hpp>

namespace omniview::synthetic {

PointCloud scan_vlp16(const Scene& scene, const std::function<Pose(double)>& T_world_lidar, const std::string& frame,
                      std::chrono::system_clock::time_point stamp, const LidarScanOptions& options) {
  const int columns = std::max(1, options.columns);
  struct Column {
    std::vector<Eigen::Vector3f> points;
    std::vector<PointCloud::Rgb> rgb;
    std::vector<uint16_t> ring;
    float time = 0;
  };
  std::vector<Column> out(columns);
  cv::parallel_for_(cv::Range(0, columns), [&](const cv::Range& range) {
    for (int k = range.start; k < range.end; ++k) {
      const double t = options.rotation_s * k / columns;
      const Pose T = T_world_lidar(t);
      const double azimuth = 2 * M_PI * k / columns;
      out[k].time = static_cast<float>(t);
      for (int ring = 0; ring < 16; ++ring) {
        const double el = vlp16_elevation_deg(ring) * M_PI / 180;
        const Vec3 dir_lidar(std::cos(el) * std::cos(azimuth), std::cos(el) * std::sin(azimuth), std::sin(el));
        const auto hit = scene.intersect(T.translation(), T.linear() * dir_lidar);
        if (!hit || hit->t < options.min_range || hit->t > options.max_range) continue;
        out[k].points.push_back((dir_lidar * hit->t).cast<float>());
        out[k].ring.push_back(static_cast<uint16_t>(ring));
        if (options.keep_colour) {
          const Vec3 bgr = scene.colour(*hit);
          out[k].rgb.push_back({cv::saturate_cast<uint8_t>(bgr[2]), cv::saturate_cast<uint8_t>(bgr[1]),
                                cv::saturate_cast<uint8_t>(bgr[0])});
        }
      }
    }
  });
  PointCloud cloud;
  cloud.frame = frame;
  cloud.stamp = stamp;
  for (const auto& c : out) {
    cloud.points.insert(cloud.points.end(), c.points.begin(), c.points.end());
    cloud.ring.insert(cloud.ring.end(), c.ring.begin(), c.ring.end());
    cloud.rgb.insert(cloud.rgb.end(), c.rgb.begin(), c.rgb.end());
    cloud.time.insert(cloud.time.end(), c.points.size(), c.time);
  }
  return cloud;
}

PointCloud scan_vlp16(const Scene& scene, const Pose& T_world_lidar, const std::string& frame,
                      std::chrono::system_clock::time_point stamp, const LidarScanOptions& options) {
  return scan_vlp16(scene, [&](double) { return T_world_lidar; }, frame, stamp, options);
}

}  // namespace omniview::synthetic
