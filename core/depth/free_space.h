// Where a lidar saw through: the rays from the sensor to its points cross empty space, so
// an object a ray passed under ends above that ray. Columns (column_completion.h) carry
// each object's sides down to the ground; under a table, a shelf or a truck's bed that
// filled the space the lidar's lower rings looked through (a desk at the height of Spot's
// lidar: its underside seen by the upper rings, the floor under it by the lower ones).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace omniview {

class SensorRays {
 public:
  // `points` (any frame, z up) measured from `sensor`, each where flags[i] & kSeenFrom is
  // set (the other points, and non-finite ones, are no ray of this sensor: a depth camera's,
  // or an older rotation's from where the robot stood then).
  static constexpr uint8_t kSeenFrom = 2;
  SensorRays(const std::vector<Eigen::Vector3f>& points, const std::vector<uint8_t>& flags,
             const Eigen::Vector3f& sensor);

  // The highest height, between `floor_z` and `below_z`, at or above which `min_rays` rays
  // cross the vertical line at `xy` (passing within `radius` of it and ending past it);
  // none where fewer do. What stands at `xy` with its lowest point at `below_z` ends above it.
  std::optional<float> highest_crossing(const Eigen::Vector2f& xy, float below_z, float floor_z, float radius,
                                        int min_rays = 2) const;

  bool empty() const { return count_ == 0; }

 private:
  // Ray ends by azimuth around the sensor, kBins to a turn (0.5 deg: a VLP-16's 0.2 deg
  // steps put a few of each ring in a bin).
  static constexpr int kBins = 720;
  struct Ray {
    Eigen::Vector2f dir;  // horizontal, unit
    float range;          // horizontal, to its end
    float slope;          // height gained per metre of horizontal range
  };
  Eigen::Vector3f sensor_;
  std::vector<Ray> rays_;           // by bin
  std::vector<uint32_t> bin_start_;  // kBins + 1 offsets into rays_
  size_t count_ = 0;
  static int bin_of(const Eigen::Vector2f& d);
};

}  // namespace omniview
