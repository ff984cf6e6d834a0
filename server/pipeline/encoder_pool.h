// Encodes rendered view frames off the render threads, in two lanes, so that a client of
// an expensive encoding (PNG of a 2048x1024 panorama: ~100 ms) never delays anyone else.
//
//   render thread ──submit(view, key, job)──▶ the group's pending slot ──▶ its lane's queue
//   lane thread: take a group's job → encode → offer to the group's subscribers at once
//
// A group is one view's frames in one EncodingKey: encoded once however many clients
// share it. A group has at most one job running and one waiting; a newer frame replaces
// the waiting one (its subscribers count it as dropped), so memory stays bounded however
// slow an encoding is, and a group's frames reach its subscribers in order.
//
// Lanes: `fast` (JPEG, raw) and `slow` (PNG, or anything over kSlowLanePixels), each with
// its own threads, so a cheap encoding never queues behind an expensive one. Slow-lane
// threads also run at a lower priority: on a busy machine the render threads and the fast
// lane get the cores first, and the expensive streams take what is left.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "server/pipeline/subscriber.h"

namespace omniview {

class EncoderPool {
 public:
  struct Job {
    std::function<void()> run;      // encodes and offers; must not throw
    std::function<void()> dropped;  // called instead when a newer frame replaced it
  };

  static constexpr long kSlowLanePixels = 4L << 20;
  // Whether frames of this size and encoding go to the slow lane.
  static bool expensive(const EncodingKey& key, int width, int height);

  // Starts the lanes' threads (at least one each).
  EncoderPool(int fast_threads, int slow_threads);
  ~EncoderPool();
  EncoderPool(const EncoderPool&) = delete;
  EncoderPool& operator=(const EncoderPool&) = delete;

  // `view` only identifies the group (with `key`). Never waits for an encode.
  void submit(const void* view, const EncodingKey& key, bool expensive, Job job);
  // Whether the group has a job waiting: it is behind, and a newer frame would only
  // replace that job, so the render thread need not render one for it.
  bool behind(const void* view, const EncodingKey& key);
  // Drops waiting jobs, lets running ones finish, joins the threads; later submits are
  // dropped. Idempotent.
  void stop();

 private:
  struct GroupKey {
    const void* view;
    EncodingKey key;
    auto operator<=>(const GroupKey&) const = default;
  };
  struct Group {
    std::optional<Job> waiting;
    bool running = false;
    bool slow = false;  // the lane of the waiting job
  };
  struct Lane {
    std::deque<GroupKey> ready;  // groups with a waiting job and none running
    std::condition_variable wake;
    std::vector<std::thread> threads;
  };

  Lane& lane(bool slow) { return slow ? slow_ : fast_; }
  void work(Lane& lane);

  std::mutex mutex_;
  std::mutex join_mutex_;
  std::map<GroupKey, Group> groups_;  // only groups with a job waiting or running
  Lane fast_;
  Lane slow_;
  bool stopping_ = false;
};

}  // namespace omniview
