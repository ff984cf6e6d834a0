#include "server/pipeline/depth/depth_update_queue.h"

#include <algorithm>
#include <ctime>
#include <exception>
#include <iostream>

#include "core/map/parallel_rows.h"

namespace omniview {
namespace {

std::chrono::steady_clock::duration process_cpu_time() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::seconds(t.tv_sec) +
                                                                          std::chrono::nanoseconds(t.tv_nsec));
}

}  // namespace

DepthUpdateQueue::DepthUpdateQueue(Update update, double rest_factor)
    : update_(std::move(update)), rest_factor_(rest_factor), thread_([this] { run(); }) {}

DepthUpdateQueue::~DepthUpdateQueue() { stop(); }

void DepthUpdateQueue::request(const std::string& view) {
  {
    std::lock_guard lock(mutex_);
    if (stopped_ || std::find(pending_.begin(), pending_.end(), view) != pending_.end()) return;
    pending_.push_back(view);
  }
  wake_.notify_one();
}

void DepthUpdateQueue::stop() {
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
    pending_.clear();
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void DepthUpdateQueue::run() {
  using Clock = std::chrono::steady_clock;
  // Serially on this thread: OpenCV's pool stays with the frame path (core/map/parallel_rows.h).
  const BackgroundThread background;
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [&] { return stopped_ || !pending_.empty(); });
    if (stopped_) return;
    const std::string view = pending_.front();
    pending_.pop_front();
    lock.unlock();
    const auto t0 = Clock::now();
    const auto cpu0 = process_cpu_time();
    try {
      update_(view);
    } catch (const std::exception& e) {
      // A view deleted or changed meanwhile is the update's to say; anything else must not
      // end the thread (the view keeps its previous map).
      std::cerr << "omniviewd: view '" << view << "': depth not updated: " << e.what() << "\n";
    }
    // The update's map build, gap fill and range images run on OpenCV's pool, on every
    // core: its wall time undercounts what it costs. The process's CPU time over the update
    // counts that (and the frames' share beside it, which errs on the side of frames):
    // resting on wall time alone, two depth views on spot-mock took half a core, not a third.
    const auto took = std::max<Clock::duration>(Clock::now() - t0, process_cpu_time() - cpu0);
    const auto rest = std::chrono::duration_cast<Clock::duration>(took * rest_factor_);
    lock.lock();
    wake_.wait_for(lock, rest, [&] { return stopped_; });
    if (stopped_) return;
  }
}

}  // namespace omniview
