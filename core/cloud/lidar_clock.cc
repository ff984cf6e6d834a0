#include "core/cloud/lidar_clock.h"

#include <algorithm>

namespace omniview {

std::chrono::system_clock::time_point vlp16_packet_time(uint32_t us_past_hour, std::chrono::system_clock::time_point received) {
  using namespace std::chrono;
  const auto hour = floor<hours>(received);
  auto t = hour + microseconds(us_past_hour);
  // Nearest of this hour, the one before and the one after.
  for (const auto candidate : {t - hours(1), t + hours(1)}) {
    if (abs(duration_cast<microseconds>(candidate - received)) < abs(duration_cast<microseconds>(t - received))) t = candidate;
  }
  return time_point_cast<system_clock::duration>(t);
}

std::chrono::system_clock::duration LidarClock::offset() const { return std::min(min_current_, min_previous_); }

LidarClock::TimePoint LidarClock::to_local(TimePoint lidar, TimePoint received) {
  const auto late = received - lidar;  // network latency, plus the clocks' difference
  if (!started_ || received - window_start_ >= 2 * kWindow || received < window_start_) {
    // First packet, or a gap (or our clock stepped back): start afresh.
    started_ = true;
    window_start_ = received;
    min_current_ = min_previous_ = late;
  } else if (received - window_start_ >= kWindow) {
    window_start_ = received;
    min_previous_ = min_current_;
    min_current_ = late;
  } else {
    min_current_ = std::min(min_current_, late);
  }
  const auto o = offset();
  synchronised_ = o > -kSyncedWithin && o < kSyncedWithin;
  return synchronised_ ? lidar : lidar + o;
}

}  // namespace omniview
