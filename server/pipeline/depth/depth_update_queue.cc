#include "server/pipeline/depth/depth_update_queue.h"

#include <algorithm>
#include <exception>
#include <iostream>

namespace omniview {

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
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [&] { return stopped_ || !pending_.empty(); });
    if (stopped_) return;
    const std::string view = pending_.front();
    pending_.pop_front();
    lock.unlock();
    const auto t0 = Clock::now();
    try {
      update_(view);
    } catch (const std::exception& e) {
      // A view deleted or changed meanwhile is the update's to say; anything else must not
      // end the thread (the view keeps its previous map).
      std::cerr << "omniviewd: view '" << view << "': depth not updated: " << e.what() << "\n";
    }
    const auto rest = std::chrono::duration_cast<Clock::duration>((Clock::now() - t0) * rest_factor_);
    lock.lock();
    wake_.wait_for(lock, rest, [&] { return stopped_; });
    if (stopped_) return;
  }
}

}  // namespace omniview
