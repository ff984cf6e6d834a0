#include "server/sources/delivery_thread.h"

#include <sys/resource.h>
#include <unistd.h>

#include <stdexcept>

namespace omniview {

namespace {
constexpr int kBackgroundNice = 10;
}  // namespace

void DeliveryThread::start(std::function<void()> body) {
  std::lock_guard lock(mutex_);
  if (started_) throw std::logic_error("source started twice");
  started_ = true;
  stopping_ = false;
  thread_ = std::thread([body = std::move(body)] {
    // Reading and decoding files ahead of their time is background work: let the render
    // threads (frames clients are waiting for) have the cores first. Linux applies nice
    // per thread; lowering it needs no privilege. Best effort: ignore failure.
    setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), kBackgroundNice);
    body();
  });
}

void DeliveryThread::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  std::lock_guard join_lock(join_mutex_);
  if (thread_.joinable()) thread_.join();
}

bool DeliveryThread::wait_until(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock lock(mutex_);
  return !wake_.wait_until(lock, deadline, [this] { return stopping_; });
}

bool DeliveryThread::running() const {
  std::lock_guard lock(mutex_);
  return started_ && !stopping_;
}

}  // namespace omniview
