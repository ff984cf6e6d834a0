// Puts a driver's capture timestamps (CLOCK_MONOTONIC) on the daemon's clock
// (system_clock, what FrameSet::capture_time and the API's timestamps use), so a frame's
// age counts from when the sensor took it, not from when USB delivered it.
#pragma once

#include <chrono>
#include <cstdint>

namespace omniview::insta360 {

class CaptureClock {
 public:
  using Sys = std::chrono::system_clock;
  using Steady = std::chrono::steady_clock;  // CLOCK_MONOTONIC on Linux, as V4L2 uses

  // The capture time of a frame stamped `monotonic` by the driver and dequeued at
  // `dequeued`, with `now_steady`/`now_system` read together. A missing (0), future or
  // implausibly old (> 1 s before dequeue) stamp falls back to the dequeue time, and
  // is counted: a driver that lies must not make frames look older or newer than they are.
  Sys::time_point to_system(std::chrono::nanoseconds monotonic, Steady::time_point dequeued,
                            Steady::time_point now_steady, Sys::time_point now_system);
  Sys::time_point to_system(std::chrono::nanoseconds monotonic, Steady::time_point dequeued) {
    return to_system(monotonic, dequeued, Steady::now(), Sys::now());
  }
  uint64_t fallbacks() const { return fallbacks_; }

 private:
  uint64_t fallbacks_ = 0;
};

}  // namespace omniview::insta360
