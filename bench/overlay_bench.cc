// The bird's-eye robot overlay: re-rendering the Spot-like model into an 800x800 layer
// (OSMesa llvmpipe), and compositing the cached layer over a frame when nothing moved,
// with OpenCV's full-frame blends measured in the same run as the anchors.
// Run: ./overlay_bench (see bench/README.md).
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>

#include "core/robot/model/urdf_loader.h"
#include "core/robot/overlay/composite.h"
#include "core/robot/overlay/robot_overlay.h"

namespace omniview::robot {
namespace {

std::shared_ptr<const RobotModel> spot_like() {
  static const auto model =
      std::make_shared<const RobotModel>(load_urdf_file(OMNIVIEW_SOURCE_DIR "/config/robots/spot/spot_like.urdf"));
  return model;
}

JointPositions standing() {
  JointPositions q;
  for (const char* leg : {"fl", "fr", "hl", "hr"}) {
    q[std::string(leg) + ".hx"] = 0;
    q[std::string(leg) + ".hy"] = 0.8;
    q[std::string(leg) + ".kn"] = -1.6;
  }
  return q;
}

// config/spot.yaml's bird's-eye view (3 m above the footprint, 110 deg: the robot covers
// ~125x60 px), or a close one (40 deg: ~480x220 px) as the costlier case. The footprint is
// 0.5 m below the body.
struct Setup {
  PinholeCamera camera;
  Pose T_robot_camera;
  explicit Setup(double hfov_deg) {
    ViewSpec s = default_view_spec(ViewType::kBirdseye);
    s.width = s.height = 800;
    s.hfov_deg = hfov_deg;
    s.height_m = 3.0;
    s.ground_z = -0.5;
    camera = pinhole_camera_of(s);
    T_robot_camera = T_frame_optical(s);
  }
};

void BM_Render(benchmark::State& state, double hfov_deg) {
  const Setup setup(hfov_deg);
  RobotOverlay overlay(spot_like(), OverlayStyle{1});
  overlay.set_joint_positions(standing());
  double kn = -1.6;
  for (auto _ : state) {
    kn = kn < -1.5 ? -1.4 : -1.6;  // a joint moved: every iteration re-renders
    overlay.set_joint_positions({{"fl.kn", kn}});
    benchmark::DoNotOptimize(overlay.layer(setup.camera, setup.T_robot_camera).bbox);
  }
  state.counters["renders"] = overlay.render_count();
}

// Per frame when nothing moved: the cache check plus compositing at opacity 0.8.
void BM_CompositeUnchanged(benchmark::State& state, double hfov_deg, int channels) {
  const Setup setup(hfov_deg);
  RobotOverlay overlay(spot_like(), OverlayStyle{1});
  overlay.set_joint_positions(standing());
  cv::Mat frame(800, 800, channels == 3 ? CV_8UC3 : CV_8UC1);
  cv::randu(frame, 0, 256);
  for (auto _ : state) {
    overlay.set_joint_positions(standing());  // as a robot-state update would, unchanged
    composite(overlay.layer(setup.camera, setup.T_robot_camera), frame, 0.8);
    benchmark::ClobberMemory();
  }
  state.counters["renders"] = overlay.render_count();
  state.counters["layer_px"] = overlay.layer(setup.camera, setup.T_robot_camera).bbox.area();
}

// Anchors: what an OpenCV user would write to blend a full-frame layer.
void BM_AnchorAddWeighted(benchmark::State& state) {
  cv::Mat frame(800, 800, CV_8UC3), layer(800, 800, CV_8UC3), out;
  cv::randu(frame, 0, 256);
  cv::randu(layer, 0, 256);
  for (auto _ : state) {
    cv::addWeighted(frame, 0.2, layer, 0.8, 0, out);
    benchmark::ClobberMemory();
  }
}

void BM_AnchorCopyToMasked(benchmark::State& state) {
  const Setup setup(110);
  RobotOverlay overlay(spot_like());
  overlay.set_joint_positions(standing());
  const OverlayLayer& layer = overlay.layer(setup.camera, setup.T_robot_camera);
  cv::Mat bgr, alpha;
  cv::extractChannel(layer.bgra, alpha, 3);
  cv::Mat channels[4];
  cv::split(layer.bgra, channels);
  cv::merge(channels, 3, bgr);
  cv::Mat frame(800, 800, CV_8UC3);
  cv::randu(frame, 0, 256);
  for (auto _ : state) {
    bgr.copyTo(frame, alpha);
    benchmark::ClobberMemory();
  }
}

BENCHMARK_CAPTURE(BM_Render, birdseye_800x800_hfov110, 110.0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Render, birdseye_800x800_hfov40, 40.0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CompositeUnchanged, birdseye_800x800_hfov110_bgr, 110.0, 3)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CompositeUnchanged, birdseye_800x800_hfov40_bgr, 40.0, 3)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CompositeUnchanged, birdseye_800x800_hfov40_grey, 40.0, 1)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_AnchorAddWeighted)->Name("BM_Anchor_cv_addWeighted_800x800_bgr")->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_AnchorCopyToMasked)->Name("BM_Anchor_cv_copyTo_masked_800x800_bgr")->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
}  // namespace omniview::robot

int main(int argc, char** argv) {
  cv::setNumThreads(2);  // as map_bench: the 2-core budget (llvmpipe: LP_NUM_THREADS, default all cores)
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
