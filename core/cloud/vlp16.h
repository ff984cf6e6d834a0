// Velodyne VLP-16 UDP data packets, decoded and assembled into full rotations.
//
// Packet facts (VLP-16 User Manual, "Data Packet Format" and "Timing"): the UDP payload of
// a data packet (port 2368 by default) is 1206 bytes: 12 data blocks of 100 bytes, a
// 4-byte timestamp (microseconds past the top of the hour, little-endian) and 2 factory
// bytes (return mode: 0x37 strongest, 0x38 last, 0x39 dual; product 0x22 = VLP-16). A block
// is the flag 0xFF 0xEE, an azimuth (uint16 LE, 0.01 deg, 0..35999, clockwise seen from
// above, 0 along the sensor's y axis), then 32 channels of distance (uint16 LE, 2 mm; 0 =
// no return) and reflectivity (uint8): lasers 0..15 of the first firing sequence, then of
// the second, whose azimuth lies halfway to the next block's. Lasers fire 2.304 us apart,
// sequences 55.296 us apart. In dual-return mode blocks come in pairs (last, strongest)
// of the same firings.
//
// Points are given in REP-103 axes (x forward, y left, z up), as the ROS velodyne driver
// does: x = r cos(el) cos(az), y = -r cos(el) sin(az), z = r sin(el).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "core/cloud/lidar_clock.h"
#include "core/cloud/point_cloud.h"

namespace omniview {

inline constexpr size_t kVlp16PacketSize = 1206;

struct Vlp16Calibration {
  // Elevation of each laser id (0..15), degrees: the data sheet's -15, 1, -13, 3, ... 15.
  std::array<double, 16> elevation_deg{-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15};
  double min_range_m = 0.4;   // returns closer than this are dropped (inside the sensor's blind zone)
  double max_range_m = 130;
};

enum class Vlp16Returns { kAll, kStrongest, kLast };

// Laser id -> ring (0 = lowest elevation), for PointCloud::ring.
std::array<uint16_t, 16> vlp16_rings(const Vlp16Calibration& calibration);

class Vlp16Assembler {
 public:
  Vlp16Assembler(const Vlp16Calibration& calibration, std::string frame, Vlp16Returns returns = Vlp16Returns::kAll);

  // Decodes one data packet. `received`: when it arrived, on the daemon's clock (the
  // packet's own time is mapped onto it, lidar_clock.h). Returns the rotations that this packet completed (the
  // azimuth wrapped), each with per-point times after its stamp (its first point).
  // Throws CloudFormatError naming `source` and what is wrong (size, block flag, azimuth,
  // return mode); the assembler's state is unchanged then.
  std::vector<PointCloud> add_packet(const uint8_t* data, size_t size, std::chrono::system_clock::time_point received,
                                     const std::string& source = "VLP-16 packet");

  size_t packets() const { return packets_; }
  // How the packets' own times map onto the daemon's clock (lidar_clock.h).
  const LidarClock& clock() const { return clock_; }

 private:
  void start_rotation();
  Vlp16Calibration calibration_;
  std::array<double, 16> cos_el_, sin_el_;
  std::array<uint16_t, 16> rings_;
  std::string frame_;
  Vlp16Returns returns_;
  PointCloud current_;
  bool have_current_ = false;
  std::chrono::system_clock::time_point lidar_stamp_;  // current_'s stamp by the lidar's clock
  double last_azimuth_ = -1;
  size_t packets_ = 0;
  LidarClock clock_;
};


}  // namespace omniview
