// Map build and apply for the paper's Table I views from the bundled two-fisheye rig,
// with OpenCV's own fisheye undistortion (initUndistortRectifyMap + remap) measured in
// the same run as the anchor. Run on 2 threads: ./map_bench (see bench/README.md).
#include <benchmark/benchmark.h>

#include <cstdlib>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/map/apply.h"
#include "core/map/fusion_map.h"
#include "core/rig/rig.h"
#include "core/view/view.h"
#include "reference_map.h"

namespace omniview {
namespace {

const Rig& example_rig() {
  // OMNIVIEW_BENCH_RIG measures another rig instead of the bundled example.
  const char* path = std::getenv("OMNIVIEW_BENCH_RIG");
  static const Rig rig = load_rig_yaml(path ? path : OMNIVIEW_SOURCE_DIR "/config/examples/dual_fisheye/rig.yaml");
  return rig;
}

ViewSpec table_view(ViewType type, int w, int h) {
  ViewSpec s;
  s.name = "bench";
  s.type = type;
  s.width = w;
  s.height = h;
  s.hfov_deg = 120;  // perspective: wide enough that both lenses contribute at the edges
  s.vfov_deg = 90;
  s.fov_deg = 360;
  return s;
}

std::vector<cv::Mat> random_images(const Rig& rig, int type) {
  std::vector<cv::Mat> images;
  cv::RNG rng(42);
  for (const auto& c : rig.cameras()) {
    cv::Mat img(c.height, c.width, type);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    images.push_back(img);
  }
  return images;
}

void BM_MapBuild(benchmark::State& state, ViewType type, int w, int h) {
  const auto view = View::create(table_view(type, w, h));
  for (auto _ : state) benchmark::DoNotOptimize(build_map(example_rig(), *view));
  state.counters["Mpx/s"] = benchmark::Counter(double(w) * h, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Apply(benchmark::State& state, ViewType type, int w, int h, int channels) {
  const auto view = View::create(table_view(type, w, h));
  const FusionMap map = build_map(example_rig(), *view);
  const auto images = random_images(example_rig(), channels == 3 ? CV_8UC3 : CV_8UC1);
  cv::Mat out;
  for (auto _ : state) {
    apply_map(map, images, out, channels);
    benchmark::ClobberMemory();
  }
  state.counters["Mpx/s"] = benchmark::Counter(double(w) * h, benchmark::Counter::kIsIterationInvariantRate);
}

// A view that shrinks the lenses (360 x 180 deg at 384x192: ~4.6 lens pixels per view
// pixel), applied with footprint-aware sampling (the pyramid level built per frame is
// part of the time) and with plain bilinear sampling.
void BM_ApplyShrinking(benchmark::State& state, Sampling sampling) {
  ViewSpec spec = table_view(ViewType::kEquirectangular, 384, 192);
  const auto view = View::create(spec);
  const FusionMap map = build_map(example_rig(), *view, MapPrecision::kAdaptive, sampling);
  const auto images = random_images(example_rig(), CV_8UC3);
  cv::Mat out;
  for (auto _ : state) {
    apply_map(map, images, out, 3);
    benchmark::ClobberMemory();
  }
  int deepest = 0;
  for (uint8_t l : map.camera_levels) deepest = std::max<int>(deepest, l);
  state.counters["levels"] = deepest;
}

// The anchor for map builds: the paper's per-pixel method restated (reference_map.h),
// single-threaded as the paper describes it.
void BM_ReferenceMethod(benchmark::State& state, ViewType type, int w, int h) {
  const auto view = View::create(table_view(type, w, h));
  for (auto _ : state) benchmark::DoNotOptimize(bench::reference_map(example_rig(), *view));
  state.counters["Mpx/s"] = benchmark::Counter(double(w) * h, benchmark::Counter::kIsIterationInvariantRate);
}

// The anchor: the same 1024x512, 120 deg perspective output from the front lens alone,
// the way an OpenCV user would do it.
struct OpenCvFisheye {
  cv::Matx33d K, P;
  cv::Vec4d D;
  cv::Size size{1024, 512};
  OpenCvFisheye() {
    const auto spec = describe(example_rig().cameras()[0].model);
    K = cv::Matx33d(spec.intrinsics[0], 0, spec.intrinsics[2], 0, spec.intrinsics[1], spec.intrinsics[3], 0, 0, 1);
    D = cv::Vec4d(spec.distortion[0], spec.distortion[1], spec.distortion[2], spec.distortion[3]);
    const double f = 512 / std::tan(60 * M_PI / 180);
    P = cv::Matx33d(f, 0, 511.5, 0, f, 255.5, 0, 0, 1);
  }
};

void BM_OpenCvFisheyeInitMap(benchmark::State& state) {
  const OpenCvFisheye cv_cam;
  cv::Mat map1, map2;
  for (auto _ : state) {
    cv::fisheye::initUndistortRectifyMap(cv_cam.K, cv_cam.D, cv::Matx33d::eye(), cv_cam.P, cv_cam.size, CV_16SC2,
                                         map1, map2);
    benchmark::ClobberMemory();
  }
}

void BM_OpenCvRemap(benchmark::State& state, int channels) {
  const OpenCvFisheye cv_cam;
  cv::Mat map1, map2, out;
  cv::fisheye::initUndistortRectifyMap(cv_cam.K, cv_cam.D, cv::Matx33d::eye(), cv_cam.P, cv_cam.size, CV_16SC2, map1,
                                       map2);
  const cv::Mat src = random_images(example_rig(), channels == 3 ? CV_8UC3 : CV_8UC1)[0];
  for (auto _ : state) {
    cv::remap(src, out, map1, map2, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    benchmark::ClobberMemory();
  }
  state.counters["Mpx/s"] = benchmark::Counter(1024.0 * 512, benchmark::Counter::kIsIterationInvariantRate);
}

using VT = ViewType;
BENCHMARK_CAPTURE(BM_MapBuild, perspective_512x256, VT::kPerspective, 512, 256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_MapBuild, perspective_1024x512, VT::kPerspective, 1024, 512)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_MapBuild, perspective_2048x1024, VT::kPerspective, 2048, 1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_MapBuild, cylindrical_1024x512, VT::kCylindrical, 1024, 512)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_MapBuild, fisheye_512x512, VT::kFisheye, 512, 512)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ReferenceMethod, perspective_1024x512, VT::kPerspective, 1024, 512)->Name("BM_Anchor_reference_method/perspective_1024x512")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ReferenceMethod, cylindrical_1024x512, VT::kCylindrical, 1024, 512)->Name("BM_Anchor_reference_method/cylindrical_1024x512")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ReferenceMethod, fisheye_512x512, VT::kFisheye, 512, 512)->Name("BM_Anchor_reference_method/fisheye_512x512")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OpenCvFisheyeInitMap)->Name("BM_Anchor_cv_fisheye_initUndistortRectifyMap_1024x512")->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_CAPTURE(BM_Apply, perspective_512x256_rgb, VT::kPerspective, 512, 256, 3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Apply, perspective_1024x512_rgb, VT::kPerspective, 1024, 512, 3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Apply, perspective_1024x512_grey, VT::kPerspective, 1024, 512, 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Apply, perspective_2048x1024_rgb, VT::kPerspective, 2048, 1024, 3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Apply, cylindrical_1024x512_rgb, VT::kCylindrical, 1024, 512, 3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Apply, fisheye_512x512_rgb, VT::kFisheye, 512, 512, 3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ApplyShrinking, equirect_384x192_rgb_bilinear, Sampling::kBilinear)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ApplyShrinking, equirect_384x192_rgb_footprint, Sampling::kFootprint)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OpenCvRemap, rgb, 3)->Name("BM_Anchor_cv_remap_16SC2_linear_1024x512_rgb")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OpenCvRemap, grey, 1)->Name("BM_Anchor_cv_remap_16SC2_linear_1024x512_grey")->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace omniview

int main(int argc, char** argv) {
  // The targets are for 2 threads; OMNIVIEW_BENCH_THREADS overrides.
  const char* threads = std::getenv("OMNIVIEW_BENCH_THREADS");
  cv::setNumThreads(threads ? std::atoi(threads) : 2);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
