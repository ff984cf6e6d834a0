// Many clients at once: a client that never reads loses only its own frames, the others
// keep their rate, and the daemon's memory stays bounded.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "daemon_process.h"

namespace omniview::testing {
namespace {

constexpr double kSourceHz = 10;  // low enough for the ThreadSanitizer build to keep up

std::string config_with_view() {
  return example_config(kSourceHz, R"(views:
  - {name: front, type: perspective, width: 320, height: 160, hfov_deg: 100}
)");
}

TEST(Streaming, SixteenClientsOneStalledOthersKeepTheirRateAndMemoryStaysBounded) {
  TempDir dir;
  DaemonProcess daemon(dir, config_with_view());

  // The stalled client: opens a PNG stream (big frames, so flow control bites fast) on
  // its own connection and never reads.
  auto stalled_stub = make_stub(daemon.address());
  auto stalled_ctx = make_context("", std::chrono::seconds(60));
  v1::StreamFramesRequest stalled_req;
  stalled_req.set_view("front");
  stalled_req.set_encoding(v1::RAW);
  auto stalled = stalled_stub->StreamFrames(stalled_ctx.get(), stalled_req);

  constexpr int kReaders = 15;
  constexpr double kSeconds = 4;
  std::atomic<bool> go{false};
  std::vector<int> received(kReaders, 0);
  std::vector<std::string> ended(kReaders);
  std::vector<std::thread> readers;
  long rss_early = 0;
  for (int i = 0; i < kReaders; ++i) {
    readers.emplace_back([&, i] {
      auto stub = make_stub(daemon.address());  // a connection each, like separate clients
      v1::StreamFramesRequest req;
      req.set_view("front");
      req.set_encoding(i % 3 == 0 ? v1::PNG : v1::JPEG);  // several encodings at once
      auto ctx = make_context("", std::chrono::seconds(60));
      // A connection attempt that fails on a loaded machine (seen once with three builds
      // beside the test) is retried instead of failing the call: what this test checks is
      // the streams once connected.
      ctx->set_wait_for_ready(true);
      auto reader = stub->StreamFrames(ctx.get(), req);
      v1::Frame f;
      while (!go) std::this_thread::sleep_for(std::chrono::milliseconds(5));
      const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(kSeconds);
      bool open = true;
      while (std::chrono::steady_clock::now() < end && (open = reader->Read(&f))) ++received[i];
      if (open) ctx->TryCancel();
      const grpc::Status status = reader->Finish();
      if (!open) ended[i] = "ended early: " + std::to_string(status.error_code()) + " " + status.error_message();
    });
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));  // connections up, stalled buffers full
  rss_early = daemon.rss_kb();
  go = true;
  // What the daemon saw mid-way, to explain a failure below.
  std::this_thread::sleep_for(std::chrono::duration<double>(kSeconds / 2));
  std::string clients_midway;
  {
    v1::Status mid;
    if (make_stub(daemon.address())->GetStatus(make_context().get(), {}, &mid).ok()) {
      for (const auto& c : mid.clients()) {
        clients_midway += "\n  " + c.peer() + " " + c.encoding() + " sent " + std::to_string(c.frames_sent()) +
                          " dropped " + std::to_string(c.frames_dropped());
      }
    }
  }
  for (auto& t : readers) t.join();
  const long rss_late = daemon.rss_kb();

  for (int i = 0; i < kReaders; ++i) {
    EXPECT_GE(received[i], 0.7 * kSourceHz * kSeconds)
        << "client " << i << " " << ended[i] << "\nclients mid-way:" << clients_midway << "\n" << daemon.log();
  }
  // The stalled client can pin one frame in its slot and what gRPC buffers for it; nothing
  // may grow with time.
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
  EXPECT_LT(rss_late - rss_early, 20 * 1024) << "RSS " << rss_early << " kB -> " << rss_late << " kB";
#else
  // AddressSanitizer holds freed memory in its quarantine (up to 256 MiB) and ThreadSanitizer
  // keeps shadow memory and per-thread caches for every block it has seen, so RSS grows with
  // any churn there; the release run checks this bound.
  (void)rss_early;
  (void)rss_late;
#endif

  auto stub = make_stub(daemon.address());
  v1::Status st;
  ASSERT_TRUE(stub->GetStatus(make_context().get(), {}, &st).ok());
  uint64_t stalled_drops = 0;
  for (const auto& c : st.clients()) {
    if (c.encoding() == "raw") stalled_drops = c.frames_dropped();
  }
  EXPECT_GT(stalled_drops, 10u);  // counted, not queued
  stalled_ctx->TryCancel();
}

TEST(Streaming, RateLimitAndGrayAreHonoured) {
  TempDir dir;
  DaemonProcess daemon(dir, example_config(30, R"(views:
  - {name: front, type: perspective, width: 160, height: 80}
)"));
  auto stub = make_stub(daemon.address());
  v1::StreamFramesRequest req;
  req.set_view("front");
  req.set_encoding(v1::RAW);
  req.set_gray(true);
  req.set_max_rate_hz(5);
  auto ctx = make_context();
  auto reader = stub->StreamFrames(ctx.get(), req);
  v1::Frame f;
  ASSERT_TRUE(reader->Read(&f));
  const auto start = std::chrono::steady_clock::now();
  int n = 0;
  while (n < 5 && reader->Read(&f)) ++n;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NEAR(n / s, 5, 1.5);
  EXPECT_EQ(f.channels(), 1);
  EXPECT_EQ(f.data().size(), 160u * 80u);
  ctx->TryCancel();
  reader->Finish();
}

TEST(Streaming, DeletingAViewEndsItsStreamsWithNotFound) {
  TempDir dir;
  DaemonProcess daemon(dir, config_with_view());
  auto stub = make_stub(daemon.address());
  v1::StreamFramesRequest req;
  req.set_view("front");
  auto ctx = make_context();
  auto reader = stub->StreamFrames(ctx.get(), req);
  v1::Frame f;
  ASSERT_TRUE(reader->Read(&f));
  v1::DeleteViewRequest del;
  del.set_name("front");
  v1::DeleteViewResponse r;
  ASSERT_TRUE(stub->DeleteView(make_context().get(), del, &r).ok());
  while (reader->Read(&f)) {
  }
  const auto s = reader->Finish();
  EXPECT_EQ(s.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_NE(s.error_message().find("deleted"), std::string::npos);
}

TEST(Streaming, StreamsPerClientAreLimited) {
  TempDir dir;
  DaemonProcess daemon(dir, config_with_view() + "limits: {max_streams_per_client: 2, max_streams: 4}\n");
  auto stub = make_stub(daemon.address());  // one connection: one client
  std::vector<std::unique_ptr<grpc::ClientContext>> ctxs;
  std::vector<std::unique_ptr<grpc::ClientReader<v1::Frame>>> readers;
  v1::StreamFramesRequest req;
  req.set_view("front");
  v1::Frame f;
  for (int i = 0; i < 3; ++i) {
    ctxs.push_back(make_context());
    readers.push_back(stub->StreamFrames(ctxs.back().get(), req));
  }
  // The daemon may take the three calls in any order: whichever came third is refused.
  // (Read all before closing any: a closed stream frees its place.)
  std::vector<bool> got_frame;
  for (auto& reader : readers) got_frame.push_back(reader->Read(&f));
  int open = 0;
  for (int i = 0; i < 3; ++i) {
    if (got_frame[i]) {
      ++open;
      ctxs[i]->TryCancel();
      readers[i]->Finish();
      continue;
    }
    const auto s = readers[i]->Finish();
    EXPECT_EQ(s.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << s.error_message();
    EXPECT_NE(s.error_message().find("max_streams_per_client"), std::string::npos) << s.error_message();
  }
  EXPECT_EQ(open, 2);
}

}  // namespace
}  // namespace omniview::testing
