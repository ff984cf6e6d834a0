#include "core/map/worker_threads.h"

#include <cstdlib>
#include <stdexcept>
#include <string>

#include <opencv2/core/utility.hpp>

namespace omniview {

void apply_worker_threads_from_env() {
  const char* value = std::getenv("OMNIVIEW_THREADS");
  if (value == nullptr || *value == '\0') return;
  const std::string text = value;
  size_t used = 0;
  int threads = 0;
  try {
    threads = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || threads < 1 || threads > 1024) {
    throw std::invalid_argument("OMNIVIEW_THREADS='" + text + "': expected a whole number of threads from 1 to 1024");
  }
  // OpenCV runs a parallel_for_ serially on the calling thread when set to 1.
  cv::setNumThreads(threads);
}

}  // namespace omniview
