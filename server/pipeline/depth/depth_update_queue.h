// Depth updates of views (`depth: measured`), off the frame path: one thread; at most one
// pending update per view (a request for a view already waiting is that request: it takes
// the newest geometry when it runs); and a duty cycle: after each update the thread rests
// `rest_factor` times what it cost (the process's CPU time over the update, or its wall time
// if longer: the update runs on every core), so depth updates take about 1 / (1 +
// rest_factor) of one core whatever the lidar's rate and the number of depth views, and
// frames keep the rest. Its parallel loops run serially on its own thread
// (core/map/parallel_rows.h), so frames never wait for OpenCV's pool.
// A view whose update is slow follows its geometry less often; its frames keep flowing
// with the previous map meanwhile.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace omniview {

class DepthUpdateQueue {
 public:
  using Update = std::function<void(const std::string& view)>;

  DepthUpdateQueue(Update update, double rest_factor);
  ~DepthUpdateQueue();
  DepthUpdateQueue(const DepthUpdateQueue&) = delete;
  DepthUpdateQueue& operator=(const DepthUpdateQueue&) = delete;

  void request(const std::string& view);
  // Waits for the update in progress, drops the pending ones. Idempotent.
  void stop();

 private:
  void run();

  const Update update_;
  const double rest_factor_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::string> pending_;
  bool stopped_ = false;
  std::thread thread_;
};

}  // namespace omniview
