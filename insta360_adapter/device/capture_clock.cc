#include "insta360_adapter/device/capture_clock.h"

namespace omniview::insta360 {

CaptureClock::Sys::time_point CaptureClock::to_system(std::chrono::nanoseconds monotonic, Steady::time_point dequeued,
                                                      Steady::time_point now_steady, Sys::time_point now_system) {
  const Steady::time_point captured(std::chrono::duration_cast<Steady::duration>(monotonic));
  const bool plausible = monotonic.count() > 0 && captured <= dequeued && dequeued - captured <= std::chrono::seconds(1);
  if (!plausible) ++fallbacks_;
  const Steady::time_point used = plausible ? captured : dequeued;
  return now_system - std::chrono::duration_cast<Sys::duration>(now_steady - used);
}

}  // namespace omniview::insta360
