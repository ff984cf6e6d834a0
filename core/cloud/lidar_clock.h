// A lidar's packet times on the daemon's clock.
//
// A VLP-16 stamps each packet with microseconds past the top of the hour by its own clock,
// which is the true time only when a GPS receiver (NMEA + PPS) or PTP sets it. Without one
// (most robots) it counts from power-on, so its minutes and seconds are unrelated to ours
// and a cloud stamped with them would be minutes away from every camera image. The clock
// places each packet in the hour nearest its arrival, then compares: a lidar whose times lie
// within kSyncedWithin of their arrival is taken as synchronised and its times are kept
// (they are better than arrival times, which carry the network's jitter); otherwise the
// lidar's times are moved onto ours by the smallest (arrival - lidar time) seen over the
// last two windows of kWindow, i.e. up to the fastest packet's latency, which follows
// drift and a lidar restart within seconds.
#pragma once

#include <chrono>
#include <cstdint>

namespace omniview {

class LidarClock {
 public:
  using TimePoint = std::chrono::system_clock::time_point;
  static constexpr std::chrono::milliseconds kSyncedWithin{50};
  static constexpr std::chrono::seconds kWindow{1};

  // The packet's time on the daemon's clock; `lidar`: its own time placed in an hour
  // (vlp16_packet_time below).
  TimePoint to_local(TimePoint lidar, TimePoint received);

  // After at least one packet: whether the lidar's own clock agrees with ours, and how far
  // its times are moved (zero when synchronised).
  bool synchronised() const { return synchronised_; }
  std::chrono::system_clock::duration correction() const { return synchronised_ ? std::chrono::system_clock::duration(0) : offset(); }

 private:
  std::chrono::system_clock::duration offset() const;
  bool started_ = false;
  bool synchronised_ = true;
  TimePoint window_start_{};
  std::chrono::system_clock::duration min_current_{}, min_previous_{};
};

// Microseconds past the hour placed in the hour that makes them nearest to `received` (a
// packet may arrive just after the hour turned).
std::chrono::system_clock::time_point vlp16_packet_time(uint32_t us_past_hour, std::chrono::system_clock::time_point received);

}  // namespace omniview
