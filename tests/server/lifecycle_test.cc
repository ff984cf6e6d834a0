// Starting and stopping the real daemon: config errors refuse to start with file, line and
// key; SIGTERM ends every stream with a status and the process exits cleanly; health.
#include <gtest/gtest.h>

#include <cmath>

#include <csignal>
#include <condition_variable>
#include <future>
#include <mutex>
#include <optional>
#include <thread>

#include <grpcpp/generic/generic_stub.h>

#include "daemon_process.h"

namespace omniview::testing {
namespace {

ProcessResult run_daemon(const TempDir& dir, const std::string& config_text) {
  const std::string config = dir.write("bad.yaml", config_text);
  return run_process(std::string(OMNIVIEWD) + " --config " + config);
}

TEST(Lifecycle, BadConfigsRefuseToStartNamingFileLineAndKey) {
  TempDir dir;
  struct Case {
    std::string config;
    std::string says;
  };
  const std::vector<Case> cases = {
      {example_config(10, "colour: blue\n"), "bad.yaml:8: colour: unknown key"},
      {example_config(10, "views:\n  - {name: v, type: perspective, frame: nowhere}\n"), "nowhere"},
      {example_config(10, "views:\n  - {name: v, type: perspective, hfov_deg: 200}\n"), "hfov"},
      {"listen: 127.0.0.1:0\nsources:\n  - {name: s, type: spot_v9}\n", "unknown source type 'spot_v9'"},
      {"listen: 127.0.0.1:0\nsources:\n  - {name: s, type: images, rig: missing.yaml, images: {}}\n", "missing.yaml"},
      {"listen: 0.0.0.0:0\n" + example_config(10).substr(example_config(10).find('\n') + 1), "allow_insecure_remote"},
  };
  for (const auto& c : cases) {
    const auto r = run_daemon(dir, c.config);
    EXPECT_EQ(r.exit_code, 1) << c.config << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.config << "\n" << r.output;
    EXPECT_NE(r.output.find("bad.yaml"), std::string::npos) << r.output;
  }
  const auto missing = run_process(std::string(OMNIVIEWD) + " --config /nonexistent/omniviewd.yaml");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("/nonexistent/omniviewd.yaml"), std::string::npos);
}

TEST(Lifecycle, CheckFailsWhereAStartWouldFail) {
  TempDir dir;
  const auto certs = dir.path() / "certs";
  const auto other = dir.path() / "other";
  for (const auto& d : {certs, other}) {
    ASSERT_EQ(std::system(("bash " OMNIVIEW_SOURCE_DIR "/scripts/make-test-certs.sh " + d.string()).c_str()), 0);
  }
  struct Case {
    std::string config;
    std::string says;
  };
  const std::vector<Case> cases = {
      // A view its rig cannot serve: only building it finds out.
      {example_config(10, "views:\n  - {name: v, type: perspective, frame: nowhere}\n"), "frame 'nowhere'"},
      // A source that cannot start.
      {"listen: 127.0.0.1:0\nsources:\n  - {name: s, type: images, rig: missing.yaml, images: {}}\n", "missing.yaml"},
      // A key that does not belong to the certificate, named at tls.key's line.
      {"tls: {cert: " + (certs / "server.crt").string() + ",\n      key: " + (other / "server.key").string() +
           "}\n" + example_config(10),
       "bad.yaml:2: tls.key: the private key in"},
  };
  for (const auto& c : cases) {
    const std::string config = dir.write("bad.yaml", c.config);
    const auto r = run_process(std::string(OMNIVIEWD) + " --check --config " + config);
    EXPECT_EQ(r.exit_code, 1) << c.config << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.config << "\n" << r.output;
    EXPECT_NE(r.output.find("bad.yaml"), std::string::npos) << r.output;
  }
  // And a good TLS config checks out (the credentials are built, nothing listens).
  const std::string good = dir.write("good.yaml", "tls: {cert: " + (certs / "server.crt").string() + ", key: " +
                                                      (certs / "server.key").string() + "}\n" + example_config(10));
  const auto r = run_process(std::string(OMNIVIEWD) + " --check --config " + good);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(Lifecycle, TheBundledConfigChecksOut) {
  const auto r = run_process(std::string(OMNIVIEWD) + " --check --config " + OMNIVIEW_SOURCE_DIR + "/config/omniviewd.yaml");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto help = run_process(std::string(OMNIVIEWD) + " --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("images"), std::string::npos);  // lists source types
  EXPECT_NE(help.output.find("replay"), std::string::npos);
  const auto version = run_process(std::string(OMNIVIEWD) + " --version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.output.rfind("omniviewd ", 0), 0u) << version.output;
}

TEST(Lifecycle, AnAddressInUseIsAClearError) {
  TempDir dir;
  DaemonProcess first(dir, example_config(10));
  std::string config = example_config(10);
  config.replace(config.find("127.0.0.1:0"), 11, first.address());
  const auto r = run_daemon(dir, config);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("cannot listen"), std::string::npos) << r.output;
}

TEST(Lifecycle, SigtermEndsStreamsWithAStatusAndExitsCleanly) {
  TempDir dir;
  DaemonProcess daemon(dir, example_config(10, "views:\n  - {name: front, type: perspective, width: 320, height: 160}\n"));
  auto stub = make_stub(daemon.address());
  v1::StreamFramesRequest req;
  req.set_view("front");
  auto ctx = make_context("", std::chrono::seconds(30));
  auto reader = stub->StreamFrames(ctx.get(), req);
  v1::Frame f;
  ASSERT_TRUE(reader->Read(&f));
  // And a client that stopped reading: shutdown must not wait for it.
  auto stalled_stub = make_stub(daemon.address());
  auto stalled_ctx = make_context("", std::chrono::seconds(30));
  req.set_encoding(v1::RAW);
  auto stalled = stalled_stub->StreamFrames(stalled_ctx.get(), req);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));

  const auto t0 = std::chrono::steady_clock::now();
  const auto bound = std::chrono::seconds(static_cast<int>(5 * test_time_scale()));
  auto exit_code = std::async(std::launch::async, [&] { return daemon.stop(SIGTERM, 2 * bound); });
  while (reader->Read(&f)) {
  }
  const auto s = reader->Finish();
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAVAILABLE);
  EXPECT_NE(s.error_message().find("shutting down"), std::string::npos) << s.error_message();
  EXPECT_EQ(exit_code.get(), 0);
  // Not held up by the stalled client, whose call would keep it for its 30 s deadline: the
  // bound is stretched for a sanitizer's slowdown (x3: 15 s), still short of that.
  EXPECT_LT(std::chrono::steady_clock::now() - t0, bound);
  stalled_ctx->TryCancel();
}

TEST(Lifecycle, WatchAndStreamSummariseWhenTheDaemonStops) {
  TempDir dir;
  DaemonProcess daemon(dir, example_config(10, "views:\n  - {name: front, type: perspective, width: 160, height: 80}\n"));
  const std::string cli = std::string(OMNIVIEW_CLI) + " --server " + daemon.address() + " ";
  auto watch = std::async(std::launch::async, [&] { return run_process(cli + "watch front --rate 500"); });
  auto stream = std::async(std::launch::async, [&] {
    return run_process(cli + "stream front --frames 100000 -o " + (dir.path() / "frames").string());
  });
  // Stop only once both clients receive frames: started under a sanitizer, a CLI can take
  // longer than any fixed wait to connect, and then it rightly says "cannot reach".
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20) * test_time_scale();
  int receiving = 0;
  while (receiving < 2 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    v1::Status status;
    receiving = 0;
    if (make_stub(daemon.address())->GetStatus(make_context().get(), {}, &status).ok()) {
      for (const auto& c : status.clients()) receiving += c.frames_sent() > 0 ? 1 : 0;
    }
  }
  EXPECT_EQ(receiving, 2) << daemon.log();  // and stop anyway: the clients end with it
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // a few frames each
  EXPECT_EQ(daemon.stop(SIGTERM), 0);
  const auto w = watch.get();
  EXPECT_EQ(w.exit_code, 1) << w.output;
  EXPECT_NE(w.output.find(" frames in "), std::string::npos) << w.output;  // the summary, then why
  EXPECT_NE(w.output.find("is shutting down"), std::string::npos) << w.output;
  EXPECT_EQ(w.output.find("cannot reach"), std::string::npos) << w.output;
  // A rate above limits.max_rate_hz is capped, and the client is told.
  EXPECT_NE(w.output.find("note: max_rate_hz 500"), std::string::npos) << w.output;
  EXPECT_NE(w.output.find("limits.max_rate_hz"), std::string::npos) << w.output;
  const auto s = stream.get();
  EXPECT_EQ(s.exit_code, 1) << s.output;
  EXPECT_NE(s.output.find("wrote "), std::string::npos) << s.output;
  EXPECT_NE(s.output.find("is shutting down"), std::string::npos) << s.output;
}

// grpc.health.v1.Health/Check for `service`, without the health proto: the request is
// field 1 (string), the answer field 1 (enum). Returns the answer's bytes.
std::string health_check(const std::string& address, const std::string& service) {
  auto channel = grpc::CreateChannel(address, grpc::InsecureChannelCredentials());
  grpc::GenericStub generic(channel);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  const std::string encoded =
      service.empty() ? "" : std::string("\x0a", 1) + static_cast<char>(service.size()) + service;
  grpc::Slice slice(encoded);
  grpc::ByteBuffer request(&slice, 1), response;
  // A mutex and a condition variable rather than std::promise: libstdc++'s future waits on
  // a futex ThreadSanitizer cannot see, which makes the response look raced.
  std::mutex mutex;
  std::condition_variable cv;
  std::optional<grpc::Status> done;
  generic.UnaryCall(&ctx, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request, &response,
                    [&](grpc::Status s) {
                      std::lock_guard lock(mutex);
                      done = s;
                      cv.notify_one();
                    });
  std::unique_lock lock(mutex);
  cv.wait(lock, [&] { return done.has_value(); });
  const grpc::Status status = *done;
  EXPECT_TRUE(status.ok()) << service << ": " << status.error_message();
  std::vector<grpc::Slice> slices;
  EXPECT_TRUE(response.Dump(&slices).ok());
  std::string bytes;
  for (const auto& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
  return bytes;
}

// A stream of a view whose source sends nothing (a camera not plugged in) says why on
// stderr while it waits, instead of hanging silently (fresh-clone probe of issue 29).
TEST(Lifecycle, StreamSaysWhyWhileNoFrameComes) {
  TempDir dir;
  DaemonProcess daemon(dir, "listen: 127.0.0.1:0\nsources:\n  - {name: air, type: insta360, device: /dev/omniview-test-absent}\n"
                            "views:\n  - {name: front, type: perspective, width: 160, height: 80, frame: insta360}\n");
  const auto seconds = std::to_string(static_cast<int>(std::ceil(5 * test_time_scale())));
  // The frames (none) to /dev/null, stderr to what run_process reads.
  const auto r = run_process("(timeout " + seconds + " " + std::string(OMNIVIEW_CLI) + " --server " + daemon.address() +
                             " stream front -o - 2>&1 > /dev/null)");
  EXPECT_NE(r.output.find("waiting: no frames for"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("source 'air' is not connected"), std::string::npos) << r.output;
}

TEST(Lifecycle, HealthServiceAnswersServing) {
  TempDir dir;
  DaemonProcess daemon(dir, example_config(10));
  const std::string serving("\x08\x01", 2);  // field 1 (status) = SERVING
  EXPECT_EQ(health_check(daemon.address(), ""), serving);
  EXPECT_EQ(health_check(daemon.address(), "omniview.v1.Omniview"), serving);
}

}  // namespace
}  // namespace omniview::testing
