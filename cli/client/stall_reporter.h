// While a watched view delivers no frames, says why once a second: the state of the
// view's source as the daemon reports it (robot unreachable, login refused, ...), so an
// operator can tell a robot that is away from a tool that hangs.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "cli/client/connection.h"

namespace omniview::cli {

class StallReporter {
 public:
  using Print = std::function<void(const std::string&)>;
  // Reports after `quiet` without a frame; `print` writes a line (the caller's terminal style).
  StallReporter(Connection& connection, std::string view, Print print,
                std::chrono::milliseconds quiet = std::chrono::milliseconds(2000));
  ~StallReporter();  // stops and joins
  StallReporter(const StallReporter&) = delete;
  StallReporter& operator=(const StallReporter&) = delete;

  void frame_arrived();

 private:
  void run();
  std::string why() const;

  Connection& connection_;
  const std::string view_;
  const Print print_;
  const std::chrono::milliseconds quiet_;
  std::atomic<int64_t> last_frame_ns_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace omniview::cli
