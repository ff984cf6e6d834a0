#include "spot_adapter/mock/sensors/lidar_scan.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "spot_adapter/mock/world/mock_scene.h"

namespace omniview::spot_mock {
namespace {

void append_float_le(std::string& out, float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((bits >> (8 * i)) & 0xff));  // little-endian on any host
}

}  // namespace

LidarScan scan_scene(const synthetic::Scene& scene, const Pose& T_world_lidar) {
  LidarScan scan;
  const Pose T_lidar_world = T_world_lidar.inverse();
  for (int ring = 0; ring < kLidarRings; ++ring) {
    const double elevation = (-15.0 + 30.0 * ring / (kLidarRings - 1)) * M_PI / 180;
    for (int k = 0; k < kLidarPointsPerRing; ++k) {
      const double azimuth = 2 * M_PI * k / kLidarPointsPerRing;
      const Vec3 dir(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                     std::sin(elevation));
      const auto hit = scene.intersect(T_world_lidar.translation(), T_world_lidar.linear() * dir);
      if (!hit || (hit->point - T_world_lidar.translation()).norm() > kLidarMaxRangeM) continue;
      const Vec3 p = T_lidar_world * hit->point;
      for (int c = 0; c < 3; ++c) append_float_le(scan.xyz_32f, static_cast<float>(p[c]));
      ++scan.num_points;
    }
  }
  return scan;
}

}  // namespace omniview::spot_mock
