// Per-frame cost of gain compensation: estimating the gains over the map's overlap samples
// and applying a blend map with them, against the same map applied without gains (the
// anchor, same run). Two views: 1024x512 from two colour pinholes, and config/spot.yaml's
// 1024x512 front view over the five grey Spot-like cameras. 2 threads as map_bench
// (OMNIVIEW_BENCH_THREADS overrides); see bench/README.md.
#include <benchmark/benchmark.h>

#include <cstdlib>

#include <opencv2/core.hpp>

#include "core/gain/gain_compensator.h"
#include "core/map/apply.h"
#include "core/map/fusion_map.h"
#include "core/synthetic/spot_like_rig.h"
#include "core/view/view.h"

namespace omniview {
namespace {

struct Setup {
  FusionMap map;
  std::vector<cv::Mat> images;
  int channels = 3;
};

Camera pinhole(const std::string& name, double y, double yaw_deg) {
  Camera c;
  c.name = name;
  c.model = CameraModel(PinholeRadtan(330, 330, 319.5, 239.5));
  c.width = 640, c.height = 480;
  c.T_parent_cam = make_pose(Vec3(0, y, 0), yaw_deg * M_PI / 180, 0, 0);
  c.T_parent_cam.linear() = c.T_parent_cam.linear() * R_view_optical();
  return c;
}

std::vector<cv::Mat> random_images(const Rig& rig, int type) {
  std::vector<cv::Mat> images;
  cv::RNG rng(42);
  for (const auto& c : rig.cameras()) {
    images.emplace_back(c.height, c.width, type);
    rng.fill(images.back(), cv::RNG::UNIFORM, 0, 256);
  }
  return images;
}

const Setup& two_cameras() {
  static const Setup s = [] {
    Rig rig("base");
    rig.add_camera(pinhole("left", 0.05, 30));
    rig.add_camera(pinhole("right", -0.05, -30));
    ViewSpec v = default_view_spec(ViewType::kPerspective);
    v.width = 1024, v.height = 512;
    v.hfov_deg = 110;
    v.distance = 3;
    return Setup{build_map(rig, *View::create(v)), random_images(rig, CV_8UC3), 3};
  }();
  return s;
}

const Setup& spot_front() {
  static const Setup s = [] {
    const Rig rig = synthetic::spot_like_rig();
    ViewSpec v = default_view_spec(ViewType::kPerspective);
    v.width = 1024, v.height = 512;
    v.frame = "body";
    v.position = Vec3(0.42, 0, 0);
    v.pitch_deg = 25;
    v.hfov_deg = 120;
    v.distance = 3;
    v.feather_px = 30;
    return Setup{build_map(rig, *View::create(v)), random_images(rig, CV_8UC1), 1};
  }();
  return s;
}

void BM_ApplyWithoutGains(benchmark::State& state, const Setup& (*setup)()) {
  const Setup& s = setup();
  cv::Mat out;
  for (auto _ : state) {
    apply_map(s.map, s.images, out, s.channels);
    benchmark::DoNotOptimize(out.data);
  }
}

void BM_Estimate(benchmark::State& state, const Setup& (*setup)()) {
  const Setup& s = setup();
  GainCompensator compensator;
  for (auto _ : state) benchmark::DoNotOptimize(compensator.update(s.map, s.images, s.channels).gain.data());
  state.counters["samples"] = static_cast<double>(s.map.gain_samples.size());
}

void BM_EstimateAndApply(benchmark::State& state, const Setup& (*setup)()) {
  const Setup& s = setup();
  GainCompensator compensator;
  cv::Mat out;
  for (auto _ : state) {
    apply_map(s.map, s.images, out, s.channels, compensator.update(s.map, s.images, s.channels));
    benchmark::DoNotOptimize(out.data);
  }
}

}  // namespace
}  // namespace omniview

using namespace omniview;
BENCHMARK_CAPTURE(BM_ApplyWithoutGains, two_cameras_1024x512_rgb, two_cameras)->Name("BM_Anchor_apply_blend/two_cameras_1024x512_rgb")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Estimate, two_cameras_1024x512_rgb, two_cameras)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_EstimateAndApply, two_cameras_1024x512_rgb, two_cameras)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ApplyWithoutGains, spot_front_1024x512_grey, spot_front)->Name("BM_Anchor_apply_blend/spot_front_1024x512_grey")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Estimate, spot_front_1024x512_grey, spot_front)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_EstimateAndApply, spot_front_1024x512_grey, spot_front)->Unit(benchmark::kMillisecond)->UseRealTime();

int main(int argc, char** argv) {
  const char* threads = std::getenv("OMNIVIEW_BENCH_THREADS");
  cv::setNumThreads(threads ? std::atoi(threads) : 2);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
