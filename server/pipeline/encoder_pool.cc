#include "server/pipeline/encoder_pool.h"

#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <exception>
#include <iostream>

namespace omniview {

namespace {
constexpr int kSlowLaneNice = 10;  // as the file sources' read-ahead threads
}  // namespace

bool EncoderPool::expensive(const EncodingKey& key, int width, int height) {
  return key.encoding == v1::PNG || static_cast<long>(width) * height > kSlowLanePixels;
}

EncoderPool::EncoderPool(int fast_threads, int slow_threads) {
  for (int i = 0; i < std::max(1, fast_threads); ++i) {
    fast_.threads.emplace_back([this] {
      pthread_setname_np(pthread_self(), "encode-fast");  // for top -H and perf
      work(fast_);
    });
  }
  for (int i = 0; i < std::max(1, slow_threads); ++i) {
    slow_.threads.emplace_back([this] {
      pthread_setname_np(pthread_self(), "encode-slow");
      // Linux applies nice per thread; lowering it needs no privilege. Best effort.
      setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), kSlowLaneNice);
      work(slow_);
    });
  }
}

EncoderPool::~EncoderPool() { stop(); }

void EncoderPool::submit(const void* view, const EncodingKey& key, bool expensive, Job job) {
  std::optional<Job> replaced;
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    const GroupKey k{view, key};
    Group& group = groups_[k];
    // A group already waiting is queued in a lane, and one running is re-queued when it
    // finishes: only an idle group needs queueing.
    const bool idle = !group.waiting && !group.running;
    if (group.waiting) {
      replaced = std::move(group.waiting);
    } else {
      group.slow = expensive;  // not queued yet: this job picks the lane
    }
    group.waiting = std::move(job);
    if (idle) {
      lane(expensive).ready.push_back(k);
      lane(expensive).wake.notify_one();
    }
  }
  // Outside the lock: it touches subscribers, and releases the frame it held.
  if (replaced && replaced->dropped) replaced->dropped();
}

bool EncoderPool::behind(const void* view, const EncodingKey& key) {
  std::lock_guard lock(mutex_);
  const auto it = groups_.find({view, key});
  return it != groups_.end() && it->second.waiting.has_value();
}

void EncoderPool::stop() {
  std::vector<Job> waiting;  // destroyed outside the lock
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    for (auto& [_, group] : groups_) {
      if (group.waiting) waiting.push_back(std::move(*group.waiting));
      group.waiting.reset();
    }
    fast_.ready.clear();
    slow_.ready.clear();
  }
  waiting.clear();  // outside the lock, and before waiting for the running ones
  fast_.wake.notify_all();
  slow_.wake.notify_all();
  std::lock_guard join_lock(join_mutex_);  // a second stop() waits for the first
  for (Lane* l : {&fast_, &slow_}) {
    for (auto& t : l->threads) {
      if (t.joinable()) t.join();
    }
  }
}

void EncoderPool::work(Lane& own) {
  std::unique_lock lock(mutex_);
  while (true) {
    own.wake.wait(lock, [&] { return stopping_ || !own.ready.empty(); });
    if (stopping_) return;
    const GroupKey key = own.ready.front();
    own.ready.pop_front();
    // std::map nodes stay put, and a running group is never erased: `group` stays valid.
    Group& group = groups_.at(key);
    std::optional<Job> job = std::move(group.waiting);
    group.waiting.reset();
    group.running = true;
    lock.unlock();
    try {
      if (job && job->run) job->run();
    } catch (const std::exception& e) {
      std::cerr << "omniviewd: encoding a frame failed: " << e.what() << "\n";
    }
    job.reset();  // the frame and its subscribers are released before the lock is taken
    lock.lock();
    group.running = false;
    if (!group.waiting) {
      groups_.erase(key);
    } else if (!stopping_) {
      lane(group.slow).ready.push_back(key);
      lane(group.slow).wake.notify_one();
    }
  }
}

}  // namespace omniview
