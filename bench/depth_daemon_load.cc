// Depth-aware views in the real daemon (issue 32): omniviewd on spot-mock's room (five
// cameras at 15 Hz, its lidar, and its depth cameras while a depth view is watched), the
// shipped `front` (1024x512) and `birdseye` (800x800) views, one JPEG client each, for
// 20 s after a 5 s warm-up. BM_DepthViews/0: both views on their fixed surfaces (the
// anchor, in the same run); /1: both with `depth: measured`. Counters: the daemon's own
// frame latency (frame set arrival to encoded frame, Frame.latency_ms) p50/p99, the
// daemon's CPU in % of one core, frames per second per client, the share of frames that
// stood on measured depth, and the depth updates' time as GetStatus reports it.
// Run: ./depth_daemon_load (bench/README.md).
#include <benchmark/benchmark.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>

#include <grpcpp/grpcpp.h>

#include "bench/spawned_process.h"
#include "omniview/v1/omniview.grpc.pb.h"

namespace omniview {
namespace {

namespace fs = std::filesystem;
using bench::SpawnedProcess;

constexpr double kWarmUpS = 5, kMeasureS = 20;

std::string daemon_config(const fs::path& dir, const std::string& mock_address, bool measured) {
  const std::string depth = measured ? "measured" : "fixed";
  return "listen: 127.0.0.1:0\n"
         "sources:\n"
         "  - {name: spot, type: spot, robot: " + mock_address + ", ca_file: " + (dir / "certs/ca.pem").string() +
         ", credentials_file: " + (dir / "credentials.yaml").string() +
         ",\n     cameras: [frontleft_fisheye_image, frontright_fisheye_image, left_fisheye_image,"
         " right_fisheye_image, back_fisheye_image], rate_hz: 15}\n"
         "views:\n"
         "  - {name: front, type: perspective, source: spot, width: 1024, height: 512, frame: footprint,\n"
         "     pose: {xyz: [0.42, 0, 0.52], ypr_deg: [0, 27, 0]}, hfov_deg: 115, distance: 3.0, ground: true,\n"
         "     fusion: blend, feather_px: 30, gain_compensation: true, depth: " + depth + "}\n"
         "  - {name: birdseye, type: birdseye, source: spot, width: 800, height: 800, frame: footprint,\n"
         "     pose: {xyz: [0, 0, 0], ypr_deg: [0, 90, 0]}, height_m: 3.0, ground_z: 0.0, hfov_deg: 110,\n"
         "     fusion: blend, feather_px: 30, gain_compensation: true, depth: " + depth + "}\n";
}

struct Samples {
  std::mutex mutex;
  std::vector<double> latency_ms;
  std::atomic<int> frames{0}, on_measured_depth{0};
};

// Streams `view` as JPEG; counts from `measure_from` until `until`.
void watch(const std::string& address, const std::string& view, std::chrono::steady_clock::time_point measure_from,
           std::chrono::steady_clock::time_point until, Samples& samples) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(64 << 20);
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // a connection each, like separate clients
  auto stub = v1::Omniview::NewStub(grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), args));
  grpc::ClientContext ctx;
  v1::StreamFramesRequest request;
  request.set_view(view);
  request.set_encoding(v1::JPEG);
  auto reader = stub->StreamFrames(&ctx, request);
  v1::Frame frame;
  while (reader->Read(&frame)) {
    const auto now = std::chrono::steady_clock::now();
    if (now >= until) break;
    if (now < measure_from) continue;
    ++samples.frames;
    if (frame.measured_depth() > 0) ++samples.on_measured_depth;
    std::lock_guard lock(samples.mutex);
    samples.latency_ms.push_back(frame.latency_ms());
  }
  ctx.TryCancel();
  reader->Finish();
}

void BM_DepthViews(benchmark::State& state) {
  const bool measured = state.range(0) == 1;
  const fs::path dir = fs::temp_directory_path() / ("omniview_depth_load_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // The rendered room is kept between runs: rendering it is most of spot-mock's start.
  const fs::path render_cache = fs::temp_directory_path() / "omniview_bench_render_cache";
  SpawnedProcess mock({SPOT_MOCK, "--port", "0", "--certs", (dir / "certs").string(), "--credentials",
                       (dir / "credentials.yaml").string(), "--scene", "room", "--render-cache", render_cache.string(),
                       "--ready-file", (dir / "mock_ready").string()},
                      dir / "spot_mock.log", dir / "mock_ready", std::chrono::seconds(300));
  std::ofstream(dir / "omniviewd.yaml") << daemon_config(dir, mock.ready(), measured);
  SpawnedProcess daemon({OMNIVIEWD, "--config", (dir / "omniviewd.yaml").string(), "--ready-file",
                         (dir / "ready").string()},
                        dir / "omniviewd.log", dir / "ready", std::chrono::seconds(60));

  for (auto _ : state) {
    Samples samples;
    const auto start = std::chrono::steady_clock::now();
    const auto measure_from = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                          std::chrono::duration<double>(kWarmUpS));
    const auto until = measure_from + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                          std::chrono::duration<double>(kMeasureS));
    std::vector<std::thread> clients;
    for (const char* view : {"front", "birdseye"}) {
      clients.emplace_back([&, view] { watch(daemon.ready(), view, measure_from, until, samples); });
    }
    std::this_thread::sleep_until(measure_from);
    const double cpu0 = daemon.cpu_seconds();
    for (auto& c : clients) c.join();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - measure_from).count();
    const double cpu = daemon.cpu_seconds() - cpu0;

    // The depth updates as the daemon reports them (the last update's time, per view).
    auto stub = v1::Omniview::NewStub(grpc::CreateChannel(daemon.ready(), grpc::InsecureChannelCredentials()));
    grpc::ClientContext ctx;
    v1::Status status;
    stub->GetStatus(&ctx, v1::GetStatusRequest(), &status);
    double update_ms = 0, updates = 0;
    for (const auto& v : status.views()) {
      update_ms = std::max(update_ms, v.depth_update_ms());
      updates += double(v.depth_updates());
    }

    state.SetIterationTime(wall);
    state.counters["latency_p50_ms"] = bench::percentile(samples.latency_ms, 0.5);
    state.counters["latency_p99_ms"] = bench::percentile(samples.latency_ms, 0.99);
    state.counters["daemon_cpu_pct_of_core"] = 100 * cpu / wall;
    state.counters["fps_per_client"] = samples.frames / wall / 2;
    state.counters["on_measured_depth"] = samples.frames ? double(samples.on_measured_depth) / samples.frames : 0;
    state.counters["depth_update_ms_last_max"] = update_ms;
    state.counters["depth_updates"] = updates;
  }
  fs::remove_all(dir);
}
BENCHMARK(BM_DepthViews)->Arg(0)->Arg(1)->Iterations(1)->Repetitions(3)->UseManualTime()->Unit(benchmark::kSecond);

}  // namespace
}  // namespace omniview

BENCHMARK_MAIN();
