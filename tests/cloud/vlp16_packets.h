// VLP-16 data packets made from a synthetic scene, as a sensor spinning at 10 Hz would send
// them (tests, the fuzz corpus, the decode benchmark).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/cloud/vlp16.h"
#include "core/synthetic/scene.h"

namespace omniview::test {

inline void put16(std::vector<uint8_t>& p, size_t at, uint16_t v) {
  p[at] = static_cast<uint8_t>(v);
  p[at + 1] = static_cast<uint8_t>(v >> 8);
}

// `count` single-return packets starting at firing `first_firing`; the lidar at
// T_world_lidar (REP-103 axes), azimuth 0 at firing 0.
inline std::vector<std::vector<uint8_t>> vlp16_packets(const synthetic::Scene& scene, const Pose& T_world_lidar, int count,
                                                       int first_firing = 0, uint32_t first_us = 1000) {
  const Vlp16Calibration cal;
  const double firing_us = 110.592, deg_per_firing = 360.0 * firing_us / 100000.0;  // 10 Hz
  std::vector<std::vector<uint8_t>> packets;
  for (int k = 0; k < count; ++k) {
    std::vector<uint8_t> p(kVlp16PacketSize, 0);
    for (int b = 0; b < 12; ++b) {
      const int firing = first_firing + 12 * k + b;
      const double az_block = std::fmod(firing * deg_per_firing, 360.0);
      p[100 * b] = 0xFF;
      p[100 * b + 1] = 0xEE;
      put16(p, 100 * b + 2, static_cast<uint16_t>(std::lround(az_block * 100) % 36000));
      for (int seq = 0; seq < 2; ++seq) {
        const double az = (az_block + seq * deg_per_firing / 2) * M_PI / 180;
        for (int laser = 0; laser < 16; ++laser) {
          const double el = cal.elevation_deg[laser] * M_PI / 180;
          const Vec3 dir(std::cos(el) * std::cos(az), -std::cos(el) * std::sin(az), std::sin(el));
          const auto hit = scene.intersect(T_world_lidar.translation(), T_world_lidar.linear() * dir);
          const size_t at = 100 * b + 4 + 3 * (16 * seq + laser);
          if (hit && hit->t < 130) put16(p, at, static_cast<uint16_t>(std::lround(hit->t / 0.002)));
          p[at + 2] = static_cast<uint8_t>(10 + laser);
        }
      }
    }
    const uint32_t us = first_us + static_cast<uint32_t>(std::lround((first_firing + 12 * k) * firing_us));
    for (int i = 0; i < 4; ++i) p[1200 + i] = static_cast<uint8_t>(us >> (8 * i));
    p[1204] = 0x37;  // strongest return
    p[1205] = 0x22;  // VLP-16
    packets.push_back(std::move(p));
  }
  return packets;
}

}  // namespace omniview::test
