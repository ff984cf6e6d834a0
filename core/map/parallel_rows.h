// Parallel loops of map building and depth updates, on OpenCV's thread pool unless the
// calling thread said it works in the background.
//
// OpenCV runs one parallel region at a time: a parallel_for_ started while another thread's
// holds the pool runs serially on its caller. A depth update (several parallel loops over a
// whole view, ~100 ms) took the pool from the frame path that way, and the frames that
// arrived meanwhile were rendered on one core: the p99 frame latency of two depth views on
// spot-mock rose past the 30 ms. Background work (BackgroundThread) runs its loops
// serially on its own thread instead; the frame path keeps the pool.
#pragma once

#include <opencv2/core/utility.hpp>

namespace omniview {

namespace parallel_internal {
inline thread_local bool background = false;
}  // namespace parallel_internal

// While alive, parallel_rows on this thread runs serially.
class BackgroundThread {
 public:
  BackgroundThread() : was_(parallel_internal::background) { parallel_internal::background = true; }
  ~BackgroundThread() { parallel_internal::background = was_; }
  BackgroundThread(const BackgroundThread&) = delete;
  BackgroundThread& operator=(const BackgroundThread&) = delete;

 private:
  bool was_;
};

// cv::parallel_for_ over `range`, or body(range) on a background thread.
template <typename Body>
void parallel_rows(const cv::Range& range, Body&& body) {
  if (parallel_internal::background) {
    if (!range.empty()) body(range);
  } else {
    cv::parallel_for_(range, body);
  }
}

}  // namespace omniview
