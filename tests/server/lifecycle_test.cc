// Starting and stopping the real daemon: config errors refuse to start with file, line and
// key; SIGTERM ends every stream with a status and the process exits cleanly; health.
#include <gtest/gtest.h>

#include <csignal>
#include <future>
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

TEST(Lifecycle, TheBundledConfigChecksOut) {
  const auto r = run_process(std::string(OMNIVIEWD) + " --check --config " + OMNIVIEW_SOURCE_DIR + "/config/omniviewd.yaml");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto help = run_process(std::string(OMNIVIEWD) + " --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("images"), std::string::npos);  // lists source types
  EXPECT_NE(help.output.find("replay"), std::string::npos);
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
  auto exit_code = std::async(std::launch::async, [&] { return daemon.stop(SIGTERM, std::chrono::seconds(10)); });
  while (reader->Read(&f)) {
  }
  const auto s = reader->Finish();
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAVAILABLE);
  EXPECT_NE(s.error_message().find("shutting down"), std::string::npos) << s.error_message();
  EXPECT_EQ(exit_code.get(), 0);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  stalled_ctx->TryCancel();
}

TEST(Lifecycle, HealthServiceAnswersServing) {
  TempDir dir;
  DaemonProcess daemon(dir, example_config(10));
  auto channel = grpc::CreateChannel(daemon.address(), grpc::InsecureChannelCredentials());
  grpc::GenericStub generic(channel);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  // grpc.health.v1.HealthCheckRequest{service: ""} is the empty message.
  grpc::ByteBuffer request, response;
  grpc::Slice empty("");
  request = grpc::ByteBuffer(&empty, 1);
  std::promise<grpc::Status> done;
  generic.UnaryCall(&ctx, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request, &response,
                    [&](grpc::Status s) { done.set_value(s); });
  const auto status = done.get_future().get();
  ASSERT_TRUE(status.ok()) << status.error_message();
  std::vector<grpc::Slice> slices;
  ASSERT_TRUE(response.Dump(&slices).ok());
  std::string bytes;
  for (const auto& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
  EXPECT_EQ(bytes, std::string("\x08\x01", 2));  // field 1 (status) = SERVING
}

}  // namespace
}  // namespace omniview::testing
