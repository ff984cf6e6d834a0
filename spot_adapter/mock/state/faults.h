// Faults injected on purpose (from flags at start, changed at run time by the control
// service). Shared by the gRPC threads, so every access goes through the lock.
#pragma once

#include <functional>
#include <mutex>

namespace omniview::spot_mock {

struct FaultSettings {
  int latency_ms = 0;                  // added to every bosdyn.api call
  double fail_probability = 0;         // per GetImage call: gRPC UNAVAILABLE or a header error
  double image_error_probability = 0;  // per image: STATUS_IMAGE_DATA_ERROR
  double corrupt_probability = 0;      // per image: bytes truncated or garbled
  double wrong_size_probability = 0;   // per image: cols/rows disagree with the data
  bool away = false;                   // every bosdyn.api call fails UNAVAILABLE
};

class Faults {
 public:
  explicit Faults(FaultSettings initial = {}) : settings_(initial) {}
  FaultSettings get() const {
    std::lock_guard lock(mutex_);
    return settings_;
  }
  // Applies `change` atomically; returns the settings after it.
  FaultSettings update(const std::function<void(FaultSettings&)>& change) {
    std::lock_guard lock(mutex_);
    change(settings_);
    return settings_;
  }

 private:
  mutable std::mutex mutex_;
  FaultSettings settings_;
};

// True with probability `p` (<= 0: never, >= 1: always, so tests can be exact).
bool chance(double p);

}  // namespace omniview::spot_mock
