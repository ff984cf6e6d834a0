// What clients asked of the mock, for tests and demos (read through the control service).
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace omniview::spot_mock {

struct CounterValues {
  uint64_t get_image_calls = 0;
  std::map<std::string, uint64_t> image_requests_by_source;  // requested names, known or not
  uint64_t logins_ok = 0;
  uint64_t logins_failed = 0;  // wrong credentials or locked out
  uint64_t token_refreshes = 0;
  uint64_t auth_rejections = 0;  // calls refused UNAUTHENTICATED
  uint64_t list_image_sources_calls = 0;
  uint64_t get_point_cloud_calls = 0;
  uint64_t get_robot_state_calls = 0;
};

class Counters {
 public:
  // e.g. counters.increment(&CounterValues::logins_ok)
  void increment(uint64_t CounterValues::*counter) {
    std::lock_guard lock(mutex_);
    ++(values_.*counter);
  }
  void count_image_request(const std::string& source) {
    // A client sending ever new names must not grow the map without bound.
    constexpr size_t kMaxNames = 256;
    std::lock_guard lock(mutex_);
    auto& by_source = values_.image_requests_by_source;
    const bool room = by_source.size() < kMaxNames || by_source.count(source);
    ++by_source[room ? source : "(other names)"];
  }
  CounterValues read(bool reset = false) {
    std::lock_guard lock(mutex_);
    CounterValues out = values_;
    if (reset) values_ = {};
    return out;
  }

 private:
  std::mutex mutex_;
  CounterValues values_;
};

}  // namespace omniview::spot_mock
