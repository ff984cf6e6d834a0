// Load on the real daemon: the replay source at 15 Hz, a 1024x512 perspective and an
// 800x800 bird's-eye view, 4 JPEG clients (2 per view). Reports the added latency per
// frame (p50/p99: from the frame set's arrival in the daemon to the frame in the client's
// hands, and the daemon's own arrival-to-encoded part) and the daemon's CPU use, as
// Google Benchmark counters. Run: ./daemon_load (see bench/README.md).
//
// BM_JpegBesidePng/0 and /1: two JPEG clients of `front`, alone (0) and beside one PNG
// client of a 2048x1024 panorama (1); only the JPEG clients' latency is in the
// percentiles, so the two show what an expensive client costs the cheap ones.
// OMNIVIEW_BENCH_DAEMON runs another omniviewd binary (a baseline build, say).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include <grpcpp/grpcpp.h>

#include "core/rig/rig.h"
#include "omniview/v1/omniview.grpc.pb.h"
#include "bench/spawned_process.h"
#include "server/recording/recording.h"

namespace omniview {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::system_clock;

constexpr double kSourceHz = 15;
constexpr int kRecordedFrames = 30;

const std::string kExample = OMNIVIEW_SOURCE_DIR "/config/examples/dual_fisheye";

// A short recording of the example images (as JPEG, the way a robot sends them).
void make_recording(const fs::path& folder) {
  const Rig rig = load_rig(kExample + "/rig.yaml");
  RecordingWriter writer(folder.string(), "bench");
  std::vector<RecordedImage> images;
  for (const auto& cam : rig.cameras()) {
    std::ifstream in(kExample + "/" + cam.name + ".jpg", std::ios::binary);
    images.push_back({cam.name, "jpeg", std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {})});
  }
  const auto t0 = Clock::now();
  for (int i = 0; i < kRecordedFrames; ++i) {
    writer.write(i, t0 + std::chrono::microseconds(int64_t(i * 1e6 / kSourceHz)), rig, images);
  }
}

struct Daemon {
  std::unique_ptr<bench::SpawnedProcess> process;
  std::string address;

  explicit Daemon(const fs::path& dir) {
    const fs::path config = dir / "omniviewd.yaml";
    std::ofstream(config) << "listen: 127.0.0.1:0\n"
                          << "sources:\n  - {name: robot, type: replay, recording: " << (dir / "rec").string()
                          << ", rate_hz: " << kSourceHz << "}\n"
                          << "views:\n"
                          << "  - {name: front, type: perspective, width: 1024, height: 512, hfov_deg: 120}\n"
                          << "  - {name: birdseye, type: birdseye, width: 800, height: 800, height_m: 4}\n"
                          << "  - {name: panorama, type: equirectangular, width: 2048, height: 1024}\n";
    const char* binary = std::getenv("OMNIVIEW_BENCH_DAEMON");
    process = std::make_unique<bench::SpawnedProcess>(
        std::vector<std::string>{binary && *binary ? binary : OMNIVIEWD, "--config", config.string(), "--ready-file",
                                 (dir / "ready").string()},
        dir / "omniviewd.log", dir / "ready", std::chrono::seconds(20));
    address = process->ready();
  }
  double cpu_seconds() const { return process->cpu_seconds(); }
};

// A client of its own connection streaming `view` until `seconds` after `start`.
struct Client {
  std::string view;
  v1::Encoding encoding = v1::JPEG;
  bool measured = true;  // its latencies go into the percentiles
};

struct Samples {
  std::mutex mutex;
  std::vector<double> end_to_end_ms, daemon_ms;
  std::atomic<int> frames{0};           // of measured clients
  std::atomic<int> unmeasured_frames{0};
};

void stream(const Daemon& daemon, const Client& client, std::chrono::steady_clock::time_point start, double seconds,
            Samples& samples) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(64 << 20);
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // a connection each, like separate clients
  auto stub = v1::Omniview::NewStub(grpc::CreateCustomChannel(daemon.address, grpc::InsecureChannelCredentials(), args));
  grpc::ClientContext ctx;
  v1::StreamFramesRequest req;
  req.set_view(client.view);
  req.set_encoding(client.encoding);
  auto reader = stub->StreamFrames(&ctx, req);
  v1::Frame f;
  bool warm = false;
  while (reader->Read(&f)) {
    const auto now = Clock::now();
    if (std::chrono::steady_clock::now() - start > std::chrono::duration<double>(seconds)) break;
    if (!warm) {  // the first frame waits for the stream to open: not steady state
      warm = true;
      continue;
    }
    if (!client.measured) {
      ++samples.unmeasured_frames;
      continue;
    }
    // Replay stamps capture time at delivery, so this is arrival -> in the client's hands.
    const auto captured =
        std::chrono::seconds(f.capture_time().seconds()) + std::chrono::nanoseconds(f.capture_time().nanos());
    const double e2e = std::chrono::duration<double, std::milli>(now.time_since_epoch() - captured).count();
    std::lock_guard lock(samples.mutex);
    samples.end_to_end_ms.push_back(e2e);
    samples.daemon_ms.push_back(f.latency_ms());
    ++samples.frames;
  }
  ctx.TryCancel();
  reader->Finish();
}

// Runs `clients` against a fresh daemon for 10 s per iteration and sets the counters.
void run_load(benchmark::State& state, const std::vector<Client>& clients) {
  const fs::path dir = fs::temp_directory_path() / ("omniview_load_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  make_recording(dir / "rec");
  Daemon daemon(dir);
  const double seconds = 10;
  int measured = 0;
  for (const auto& c : clients) measured += c.measured ? 1 : 0;

  for (auto _ : state) {
    Samples samples;
    std::vector<std::thread> threads;
    const auto cpu0 = daemon.cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    for (const auto& c : clients) threads.emplace_back([&, c] { stream(daemon, c, start, seconds, samples); });
    for (auto& t : threads) t.join();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double cpu = daemon.cpu_seconds() - cpu0;
    state.SetIterationTime(wall);
    state.counters["latency_p50_ms"] = bench::percentile(samples.end_to_end_ms, 0.5);
    state.counters["latency_p99_ms"] = bench::percentile(samples.end_to_end_ms, 0.99);
    state.counters["daemon_p50_ms"] = bench::percentile(samples.daemon_ms, 0.5);
    state.counters["daemon_p99_ms"] = bench::percentile(samples.daemon_ms, 0.99);
    state.counters["daemon_cpu_pct_of_core"] = 100 * cpu / wall;
    state.counters["fps_per_client"] = samples.frames / wall / measured;
    if (measured < static_cast<int>(clients.size())) {
      state.counters["fps_other_clients"] = samples.unmeasured_frames / wall / (clients.size() - measured);
    }
  }
  fs::remove_all(dir);
}

void BM_DaemonLoad(benchmark::State& state) {
  run_load(state, {{"front"}, {"birdseye"}, {"front"}, {"birdseye"}});
}
BENCHMARK(BM_DaemonLoad)->Iterations(1)->Repetitions(3)->UseManualTime()->Unit(benchmark::kSecond);

// Two JPEG clients of `front`; with argument 1 also a PNG client of the 2048x1024 panorama.
void BM_JpegBesidePng(benchmark::State& state) {
  std::vector<Client> clients = {{"front"}, {"front"}};
  if (state.range(0) == 1) clients.push_back({"panorama", v1::PNG, false});
  run_load(state, clients);
}
BENCHMARK(BM_JpegBesidePng)->Arg(0)->Arg(1)->Iterations(1)->Repetitions(3)->UseManualTime()->Unit(benchmark::kSecond);

}  // namespace
}  // namespace omniview

BENCHMARK_MAIN();
