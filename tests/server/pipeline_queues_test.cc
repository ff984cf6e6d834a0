// The pipeline's hand-off structures, without a daemon: a recording's bounded frame-set
// queue (FrameSetTap), the encoder pool's lanes and per-group slots (EncoderPool), a
// source channel's wait for the next frame set, and when a silent source's views go stale.
// Everything here is ordered by latches, not by sleeps, so it holds on a loaded machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "server/pipeline/encoder_pool.h"
#include "server/pipeline/frame_set_tap.h"
#include "server/pipeline/source_channel.h"
#include "server/pipeline/staleness.h"

namespace omniview {
namespace {

using namespace std::chrono_literals;

std::shared_ptr<const FrameSet> frame_set(uint64_t sequence, int pixels = 16) {
  auto f = std::make_shared<FrameSet>();
  f->sequence = sequence;
  f->images = {cv::Mat(1, pixels, CV_8UC1, cv::Scalar(0))};
  return f;
}

TEST(FrameSetTap, QueuesEveryFrameSetWithinItsBound) {
  FrameSetTap tap({4, 1 << 20});
  for (uint64_t s = 1; s <= 4; ++s) tap.offer(frame_set(s));
  for (uint64_t s = 1; s <= 4; ++s) {
    const auto t = tap.take(0ms);
    ASSERT_TRUE(t && t->frames);
    EXPECT_EQ(t->frames->sequence, s) << "in order, none lost";
    EXPECT_EQ(t->skipped_before, 0u);
  }
  EXPECT_FALSE(tap.take(0ms)) << "empty: a timeout, not the end";
  EXPECT_EQ(tap.skipped(), 0u);
}

TEST(FrameSetTap, SkipsBeyondItsBoundAndSaysWhere) {
  FrameSetTap tap({3, 1 << 20});
  for (uint64_t s = 1; s <= 7; ++s) tap.offer(frame_set(s));  // 4..7 do not fit
  EXPECT_EQ(tap.skipped(), 4u);
  for (uint64_t s = 1; s <= 3; ++s) EXPECT_EQ(tap.take(0ms)->skipped_before, 0u);
  tap.offer(frame_set(8));
  const auto t = tap.take(0ms);
  ASSERT_TRUE(t && t->frames);
  EXPECT_EQ(t->frames->sequence, 8u);
  EXPECT_EQ(t->skipped_before, 4u) << "1..3 taken + 4 skipped + this one = sequence 8";
}

TEST(FrameSetTap, ByteBudgetBoundsMemoryButOneAlwaysFits) {
  FrameSetTap tap({100, 1000});
  tap.offer(frame_set(1, 5000));  // more than the budget alone: still queued
  tap.offer(frame_set(2, 10));    // but nothing beside it
  EXPECT_EQ(tap.skipped(), 1u);
  EXPECT_EQ(tap.take(0ms)->frames->sequence, 1u);
  for (uint64_t s = 3; s <= 200; ++s) tap.offer(frame_set(s, 100));
  size_t queued = 0;
  while (tap.take(0ms)) ++queued;
  EXPECT_EQ(queued, 10u) << "1000 bytes of 100-byte frame sets";
}

TEST(FrameSetTap, CloseEndsTheStreamAndFreesTheQueue) {
  FrameSetTap tap;
  const auto f = frame_set(1);
  tap.offer(f);
  tap.close("shutting down");
  EXPECT_EQ(f.use_count(), 1) << "the queue let go of it";
  const auto t = tap.take(0ms);
  ASSERT_TRUE(t);
  EXPECT_FALSE(t->frames);
  EXPECT_EQ(tap.close_reason(), "shutting down");
  tap.offer(frame_set(2));
  EXPECT_FALSE(tap.take(0ms)->frames) << "closed stays closed";
}

// A job that waits until released; records when it ran.
class Gate {
 public:
  void open() {
    std::lock_guard lock(mutex_);
    open_ = true;
    changed_.notify_all();
  }
  void wait() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return open_; });
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  bool open_ = false;
};

// Runs and drops, in order, as "name" / "-name".
class Log {
 public:
  void add(const std::string& what) {
    std::lock_guard lock(mutex_);
    entries_.push_back(what);
    changed_.notify_all();
  }
  bool wait_for(const std::string& what) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, 10s, [&] { return std::find(entries_.begin(), entries_.end(), what) != entries_.end(); });
  }
  std::vector<std::string> entries() {
    std::lock_guard lock(mutex_);
    return entries_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::string> entries_;
};

EncoderPool::Job job(Log& log, const std::string& name, Gate* gate = nullptr) {
  return {[&log, name, gate] {
            log.add("start " + name);
            if (gate) gate->wait();
            log.add(name);
          },
          [&log, name] { log.add("-" + name); }};
}

const EncodingKey kJpeg{v1::JPEG, 85, false};
const EncodingKey kPng{v1::PNG, 0, false};

TEST(EncoderPool, CheapEncodingsDoNotWaitBehindExpensiveOnes) {
  EncoderPool pool(1, 1);
  Log log;
  Gate png_a, png_b;
  int view_a = 0, view_b = 0, view_c = 0;
  // Two PNG groups: one runs (blocked), one waits in the slow lane.
  pool.submit(&view_a, kPng, true, job(log, "png a", &png_a));
  ASSERT_TRUE(log.wait_for("start png a"));
  pool.submit(&view_b, kPng, true, job(log, "png b", &png_b));
  // A JPEG of a third view: done while both PNGs are still stuck.
  pool.submit(&view_c, kJpeg, false, job(log, "jpeg c"));
  EXPECT_TRUE(log.wait_for("jpeg c"));
  png_a.open();
  png_b.open();
  EXPECT_TRUE(log.wait_for("png b"));
  pool.stop();
}

TEST(EncoderPool, OneJobPerGroupAtATimeAndANewerFrameReplacesAWaitingOne) {
  EncoderPool pool(2, 1);  // two fast threads: a group still never runs twice at once
  Log log;
  Gate first;
  int view = 0;
  pool.submit(&view, kJpeg, false, job(log, "1", &first));
  ASSERT_TRUE(log.wait_for("start 1"));
  EXPECT_FALSE(pool.behind(&view, kJpeg)) << "running, nothing waiting";
  pool.submit(&view, kJpeg, false, job(log, "2"));
  EXPECT_TRUE(pool.behind(&view, kJpeg));
  EXPECT_FALSE(pool.behind(&view, kPng)) << "another group";
  pool.submit(&view, kJpeg, false, job(log, "3"));  // replaces 2, which is dropped
  first.open();
  ASSERT_TRUE(log.wait_for("3"));
  pool.stop();
  EXPECT_EQ(log.entries(), (std::vector<std::string>{"start 1", "-2", "1", "start 3", "3"}));
}

TEST(EncoderPool, StopFinishesWhatRunsDropsWhatWaitsAndRefusesMore) {
  auto pool = std::make_unique<EncoderPool>(1, 1);
  Log log;
  Gate gate;
  int view = 0;
  pool->submit(&view, kJpeg, false, job(log, "running", &gate));
  ASSERT_TRUE(log.wait_for("start running"));
  // The waiting job lets the running one go when it is destroyed, which stop() does
  // after it stopped taking jobs: so "waiting" can never start.
  EncoderPool::Job waiting = job(log, "waiting");
  waiting.dropped = [on_destroyed = std::shared_ptr<void>(nullptr, [&gate](void*) { gate.open(); })] {};
  pool->submit(&view, kJpeg, false, std::move(waiting));
  pool->stop();  // returns only once "running" is done
  pool->submit(&view, kJpeg, false, job(log, "late"));
  pool->stop();  // twice is fine
  pool.reset();
  EXPECT_EQ(log.entries(), (std::vector<std::string>{"start running", "running"}));
}

TEST(EncoderPool, PngAndHugeViewsGoToTheSlowLane) {
  EXPECT_TRUE(EncoderPool::expensive(kPng, 64, 64));
  EXPECT_FALSE(EncoderPool::expensive(kJpeg, 2048, 1024));
  EXPECT_FALSE(EncoderPool::expensive({v1::RAW, 0, false}, 2048, 2048));
  EXPECT_TRUE(EncoderPool::expensive(kJpeg, 4096, 2048));
}

TEST(SourceChannel, NextReturnsNothingAfterItsTimeoutAndNullOnceClosed) {
  struct Silent : Source {
    Silent() : Source("silent") {}
    std::string type() const override { return "test"; }
    std::shared_ptr<const Rig> rig() const override { return std::make_shared<Rig>(); }
    void start(FrameCallback) override {}
    void stop() override {}
    SourceHealth health() const override { return {}; }
  };
  SourceChannel channel(std::make_unique<Silent>());
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(channel.next(50ms), nullptr);
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 50ms);
  EXPECT_FALSE(channel.closed());
  auto f = frame_set(7);
  std::const_pointer_cast<FrameSet>(f)->arrival = std::chrono::steady_clock::now();
  channel.deliver(f);
  EXPECT_EQ(channel.next(50ms), f);
  channel.close();
  EXPECT_EQ(channel.next(10s), nullptr);  // at once
  EXPECT_TRUE(channel.closed());
}

TEST(Staleness, AfterTheLongerOfOneAndAHalfSecondsAndFourFrameIntervals) {
  const auto now = std::chrono::steady_clock::now();
  SourceStats stats;
  SourceHealth health;
  health.connected = true;
  EXPECT_FALSE(judge_staleness("cam", stats, health, {}, now).stale) << "nothing delivered yet: nothing to re-send";
  stats.last_arrival = now - 1200ms;
  stats.mean_interval_s = 1.0 / 30;
  EXPECT_FALSE(judge_staleness("cam", stats, health, {}, now).stale);
  stats.last_arrival = now - 1600ms;
  const Staleness s = judge_staleness("cam", stats, health, {}, now);
  EXPECT_TRUE(s.stale);
  EXPECT_EQ(s.reason, "no new images from source 'cam' for 1.6 s");
  stats.mean_interval_s = 2;  // a 0.5 Hz source
  EXPECT_FALSE(judge_staleness("cam", stats, health, {}, now).stale);
  stats.last_arrival = now - 8100ms;
  EXPECT_TRUE(judge_staleness("cam", stats, health, {}, now).stale);
  health.connected = false;
  health.message = "camera unplugged; looking for it every second";
  EXPECT_EQ(judge_staleness("cam", stats, health, {}, now).reason,
            "no new images from source 'cam' for 8.1 s: it is not connected (camera unplugged; looking for it every "
            "second)");
  // A view watched only since a moment ago: its source (pulling only for watchers) gets time.
  EXPECT_FALSE(judge_staleness("cam", stats, health, now - 500ms, now).stale);
  EXPECT_TRUE(judge_staleness("cam", stats, health, now - 9s, now).stale);
}

}  // namespace
}  // namespace omniview
