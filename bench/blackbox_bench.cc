// The black box's cost per frame set of a Spot (five 640x480 grey JPEGs as the robot sends
// them, quality 75), beside the anchor: decoding the same five JPEGs, which the daemon does
// for every frame set it renders anyway. The ring writes into a temporary folder with a
// 64 MB budget, so the run includes dropping old segments. Issue 31's target: at 15 Hz, at
// most 5 % of one core (3.3 ms a frame set).
#include <unistd.h>

#include <filesystem>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/io/image_codec.h"
#include "server/blackbox/black_box_ring.h"

namespace omniview {
namespace {
namespace fs = std::filesystem;

std::shared_ptr<Rig> spot_like_rig() {
  auto rig = std::make_shared<Rig>();
  for (const char* name : {"frontleft", "frontright", "left", "right", "back"}) {
    Camera cam;
    cam.name = name;
    cam.width = 640;
    cam.height = 480;
    cam.model = make_camera_model({"pinhole", "none", {330, 330, 319.5, 239.5}, {}}, name);
    rig->add_camera(cam);
  }
  return rig;
}

// Camera-like content: smoothed noise compresses as a grey room does (~35-45 kB at q75).
std::vector<uint8_t> camera_jpeg(int seed) {
  cv::Mat image(480, 640, CV_8UC1);
  cv::RNG(seed).fill(image, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(image, image, {0, 0}, 2);
  return encode_jpeg(image, 75);
}

FrameSet spot_frames(const std::shared_ptr<Rig>& rig, const std::vector<std::shared_ptr<const std::vector<uint8_t>>>& jpegs,
                     uint64_t sequence) {
  FrameSet frames;
  frames.sequence = sequence;
  frames.capture_time = std::chrono::system_clock::now();
  frames.rig = rig;
  frames.images.resize(jpegs.size());
  for (const auto& j : jpegs) frames.encoded.push_back({"jpeg", j});
  return frames;
}

std::vector<std::shared_ptr<const std::vector<uint8_t>>> five_jpegs() {
  std::vector<std::shared_ptr<const std::vector<uint8_t>>> jpegs;
  for (int i = 0; i < 5; ++i) jpegs.push_back(std::make_shared<const std::vector<uint8_t>>(camera_jpeg(i)));
  return jpegs;
}

void BM_BlackBoxKeepsASpotFrameSet(benchmark::State& state) {
  const fs::path folder = fs::temp_directory_path() / ("blackbox_bench_" + std::to_string(::getpid()));
  fs::remove_all(folder);
  const auto rig = spot_like_rig();
  const auto jpegs = five_jpegs();
  size_t bytes = 0;
  for (const auto& j : jpegs) bytes += j->size();
  {
    BlackBoxRingOptions options;
    options.max_bytes = 64u << 20;
    BlackBoxRing ring(folder / "ring", "spot", options);
    uint64_t sequence = 0;
    for (auto _ : state) ring.write(spot_frames(rig, jpegs, ++sequence));
  }
  fs::remove_all(folder);
  state.counters["frame_set_kB"] = double(bytes) / 1000;
  state.SetBytesProcessed(int64_t(state.iterations() * bytes));
}

void BM_DecodeTheSameFrameSet(benchmark::State& state) {
  const auto jpegs = five_jpegs();
  for (auto _ : state) {
    for (const auto& j : jpegs) benchmark::DoNotOptimize(decode_image(std::span<const uint8_t>(*j)).data);
  }
}

BENCHMARK(BM_BlackBoxKeepsASpotFrameSet)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_DecodeTheSameFrameSet)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace omniview

BENCHMARK_MAIN();
