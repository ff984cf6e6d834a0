// The thread a file-based source delivers from: started once, woken early by stop().
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace omniview {

class DeliveryThread {
 public:
  ~DeliveryThread() { stop(); }

  // Runs `body` on a new thread; `body` returns once wait_until() says to stop.
  void start(std::function<void()> body);
  // Asks the body to stop and joins it. Safe to call twice, and from any thread but its own.
  void stop();
  // Sleeps until `deadline`; false when stop() was called (then return at once).
  bool wait_until(std::chrono::steady_clock::time_point deadline);
  bool running() const;

 private:
  mutable std::mutex mutex_;
  std::mutex join_mutex_;  // two stop() calls at once join once
  std::condition_variable wake_;
  bool stopping_ = false;
  bool started_ = false;
  std::thread thread_;
};

}  // namespace omniview
