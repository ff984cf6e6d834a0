#include "core/cloud/vlp16.h"

#include <algorithm>
#include <cmath>

namespace omniview {
namespace {

constexpr size_t kBlocks = 12, kBlockSize = 100;
constexpr double kLaserGapUs = 2.304, kSequenceUs = 55.296;
constexpr double kDistanceUnitM = 0.002;

uint16_t u16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }

}  // namespace

std::array<uint16_t, 16> vlp16_rings(const Vlp16Calibration& calibration) {
  std::array<int, 16> order;
  for (int i = 0; i < 16; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return calibration.elevation_deg[a] < calibration.elevation_deg[b]; });
  std::array<uint16_t, 16> rings{};
  for (int r = 0; r < 16; ++r) rings[order[r]] = static_cast<uint16_t>(r);
  return rings;
}

Vlp16Assembler::Vlp16Assembler(const Vlp16Calibration& calibration, std::string frame, Vlp16Returns returns)
    : calibration_(calibration), rings_(vlp16_rings(calibration)), frame_(std::move(frame)), returns_(returns) {
  for (int i = 0; i < 16; ++i) {
    const double el = calibration.elevation_deg[i] * M_PI / 180;
    if (!std::isfinite(el)) throw std::invalid_argument("VLP-16 calibration: laser " + std::to_string(i) + " elevation is not finite");
    cos_el_[i] = std::cos(el);
    sin_el_[i] = std::sin(el);
  }
  start_rotation();
}

void Vlp16Assembler::start_rotation() {
  current_ = PointCloud();
  current_.frame = frame_;
  have_current_ = false;
  // A 10 Hz rotation has ~29 k returns: grow once, not while packets arrive.
  current_.points.reserve(32768);
  current_.time.reserve(32768);
  current_.ring.reserve(32768);
  current_.intensity.reserve(32768);
}

std::vector<PointCloud> Vlp16Assembler::add_packet(const uint8_t* data, size_t size, std::chrono::system_clock::time_point received,
                                                   const std::string& source) {
  if (size != kVlp16PacketSize) {
    throw CloudFormatError(source + ": " + std::to_string(size) + " bytes, a VLP-16 data packet has " +
                           std::to_string(kVlp16PacketSize));
  }
  // Validate the whole packet before changing any state.
  for (size_t b = 0; b < kBlocks; ++b) {
    const uint8_t* block = data + b * kBlockSize;
    if (block[0] != 0xFF || block[1] != 0xEE) {
      throw CloudFormatError(source + ": block " + std::to_string(b) + " does not start with the flag 0xFFEE");
    }
    if (u16(block + 2) >= 36000) {
      throw CloudFormatError(source + ": block " + std::to_string(b) + " azimuth " + std::to_string(u16(block + 2)) +
                             " is not below 36000 (0.01 deg)");
    }
  }
  const uint8_t mode = data[1204];
  if (mode != 0x37 && mode != 0x38 && mode != 0x39) {
    throw CloudFormatError(source + ": unknown return mode byte 0x" + [&] {
      char hex[3];
      std::snprintf(hex, sizeof hex, "%02x", mode);
      return std::string(hex);
    }() + " (0x37 strongest, 0x38 last, 0x39 dual)");
  }
  const bool dual = mode == 0x39;
  const uint32_t us = static_cast<uint32_t>(data[1200] | (data[1201] << 8) | (data[1202] << 16) | (uint32_t{data[1203]} << 24));
  // Times within a rotation come from the lidar's own clock, whose differences are exact;
  // only the rotation's stamp is moved onto ours (lidar_clock.h).
  const auto packet_time = vlp16_packet_time(us, received);
  const auto correction = clock_.to_local(packet_time, received) - packet_time;
  ++packets_;

  std::vector<PointCloud> done;
  double packet_offset_s = 0;  // this packet's time after the rotation's stamp, once known
  bool have_offset = false;
  auto azimuth_of = [&](size_t b) { return u16(data + b * kBlockSize + 2) / 100.0; };
  const size_t step = dual ? 2 : 1;  // blocks per firing
  for (size_t b = 0; b < kBlocks; ++b) {
    const uint8_t* block = data + b * kBlockSize;
    const size_t firing = b / step;
    if (dual) {
      // Even blocks: last return; odd: strongest (a copy of the last where both agree).
      if (returns_ == Vlp16Returns::kLast && b % 2 == 1) continue;
      if (returns_ == Vlp16Returns::kStrongest && b % 2 == 0) continue;
    }
    const double az0 = azimuth_of(b);
    // The second sequence's azimuth: halfway to the next firing's block (or, for the last,
    // continuing the previous gap).
    double gap;
    if (b + step < kBlocks) {
      gap = azimuth_of(b + step) - az0;
    } else if (b >= step) {
      gap = az0 - azimuth_of(b - step);
    } else {
      gap = 0.4;
    }
    if (gap < 0) gap += 360;
    if (gap > 5) gap = 0.4;  // a jump (packet loss): assume the 10 Hz step
    for (int seq = 0; seq < 2; ++seq) {
      const double az = std::fmod(az0 + seq * gap / 2, 360.0);
      if (az < last_azimuth_ && have_current_) {  // wrapped: a full rotation is done
        done.push_back(std::move(current_));
        start_rotation();
        have_offset = false;
      }
      last_azimuth_ = az;
      const double az_rad = az * M_PI / 180;
      const double ca = std::cos(az_rad), sa = std::sin(az_rad);
      for (int laser = 0; laser < 16; ++laser) {
        const uint8_t* ch = block + 4 + 3 * (16 * seq + laser);
        const uint16_t raw = u16(ch);
        if (raw == 0) continue;
        if (dual && b % 2 == 1 && returns_ == Vlp16Returns::kAll && u16(data + (b - 1) * kBlockSize + 4 + 3 * (16 * seq + laser)) == raw) {
          continue;  // the strongest return is the last one: already taken
        }
        const double r = raw * kDistanceUnitM;
        if (r < calibration_.min_range_m || r > calibration_.max_range_m) continue;
        const double t_us = firing * 2 * kSequenceUs + seq * kSequenceUs + laser * kLaserGapUs;
        if (!have_current_) {
          lidar_stamp_ = packet_time + std::chrono::duration_cast<std::chrono::system_clock::duration>(
                                           std::chrono::duration<double, std::micro>(t_us));
          current_.stamp = lidar_stamp_ + correction;
          have_current_ = true;
        }
        if (!have_offset) {
          packet_offset_s = std::chrono::duration<double>(packet_time - lidar_stamp_).count();
          have_offset = true;
        }
        const double xy = r * cos_el_[laser];
        current_.points.emplace_back(static_cast<float>(xy * ca), static_cast<float>(-xy * sa), static_cast<float>(r * sin_el_[laser]));
        current_.time.push_back(static_cast<float>(packet_offset_s + t_us * 1e-6));
        current_.ring.push_back(rings_[laser]);
        current_.intensity.push_back(ch[2]);
      }
    }
  }
  return done;
}

}  // namespace omniview
