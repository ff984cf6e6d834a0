// Depth update of a measured-depth view (issue 32): a 1024x512 front perspective view over
// the Spot-like rig's five cameras, from one VLP-16 rotation (~29 k points) and from ten
// accumulated rotations (~290 k), in the bundled example's room. One update = the columns
// that complete the points (core/depth/column_completion.h), the surface
// from the points (splat, gap fill, blend with the fixed surface), the cameras' occlusion
// buffers, and the map build with occlusion (adaptive; the exact one beside it). The anchor, in the same run: today's
// fixed map build of the same view. Run on 2 threads: ./depth_bench (see bench/README.md).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>

#include <opencv2/core/utility.hpp>

#include "core/depth/camera_occluders.h"
#include "core/depth/column_completion.h"
#include "core/depth/measured_depth_view.h"
#include "core/map/fusion_map.h"
#include "core/synthetic/lidar_scan.h"
#include "core/synthetic/scene.h"
#include "core/synthetic/spot_like_rig.h"

namespace omniview {
namespace {

const Pose kWorldBody = make_pose(Vec3(0.5, 0.3, 0.5), 0, 0, 0);  // the body 0.5 m above the room's floor
const Pose kBodyLidar = make_pose(Vec3(-0.1, 0, 0.3), 0, 0, 0);

const Rig& rig() {
  static const Rig r = synthetic::spot_like_rig();
  return r;
}

const CameraRangeImages& range_images() {  // made once per rig, as the daemon would
  static const CameraRangeImages images(rig(), ViewOcclusionOptions{}.cell_deg);
  return images;
}

ViewSpec front_view(Depth depth) {
  ViewSpec s;
  s.name = "front";
  s.type = ViewType::kPerspective;
  s.width = 1024;
  s.height = 512;
  s.position = Vec3(0.42, 0, 0.02);
  s.pitch_deg = 27;
  s.hfov_deg = 100;
  s.distance = 3;
  s.ground = true;
  s.ground_z = -0.5;
  s.depth = depth;
  return s;
}

// `rotations` VLP-16 rotations from poses a few centimetres and degrees apart (a robot
// moving slowly), in the body frame, with their top rings (column_completion.h).
struct LidarPoints {
  std::vector<Eigen::Vector3f> points;
  std::vector<uint8_t> top;
};
const LidarPoints& lidar(int rotations) {
  static std::map<int, LidarPoints> cache;
  auto& out = cache[rotations];
  if (!out.points.empty()) return out;
  const synthetic::Scene room = synthetic::Scene::room();
  for (int k = 0; k < rotations; ++k) {
    const Pose motion = make_pose(Vec3(0.03 * k, 0.01 * k, 0), 0.01 * k, 0, 0);
    const Pose T_body_lidar = motion * kBodyLidar;
    const PointCloud scan = synthetic::scan_vlp16(room, kWorldBody * T_body_lidar, "lidar", {});
    for (const auto& p : scan.points) out.points.push_back((T_body_lidar * p.cast<double>()).cast<float>());
    // The first rotation's rays start at kBodyLidar (the others' where the robot had moved).
    const std::vector<uint8_t> top = k == 0 ? lidar_flags(scan.points) : top_of_field(scan.points);
    out.top.insert(out.top.end(), top.begin(), top.end());
  }
  return out;
}
const std::vector<Eigen::Vector3f>& lidar_points(int rotations) { return lidar(rotations).points; }

void BM_DepthUpdate(benchmark::State& state, int rotations, bool with_columns) {
  const ViewSpec spec = front_view(Depth::kMeasured);
  const DepthSurface surface(spec);
  const LidarPoints& l = lidar(rotations);
  const Pose T_view_body = spec.T_frame_view().inverse();
  size_t added = 0;
  for (auto _ : state) {
    const Completion completion = with_columns ? complete_columns(rig(), l.points, l.top,
                                                                  kBodyLidar.translation().cast<float>())
                                               : Completion{};
    const auto view = surface.update(l.points, T_view_body, nullptr, &completion.points);
    const Occlusion occlusion = view_occlusion(range_images(), *view, l.points, T_view_body, {}, &completion.points);
    benchmark::DoNotOptimize(build_map(rig(), *view, MapPrecision::kAdaptive, Sampling::kFootprint, &occlusion));
    added = completion.points.size();
  }
  state.counters["points"] = double(l.points.size());
  state.counters["columns_points"] = double(added);
}

// The columns alone (once per geometry in the daemon, shared by its depth views).
// `see_through` false: no ray told (free_space.h), what judging the columns by them costs.
void BM_ColumnCompletionOnly(benchmark::State& state, int rotations, bool see_through) {
  const LidarPoints& l = lidar(rotations);
  std::vector<uint8_t> flags = l.top;
  if (!see_through) {
    for (auto& f : flags) f &= uint8_t(~SensorRays::kSeenFrom);
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(complete_columns(rig(), l.points, flags, kBodyLidar.translation().cast<float>()));
  }
}

// The parts of one update, to see where its time goes.
void BM_DepthSurfaceOnly(benchmark::State& state, int rotations) {
  const ViewSpec spec = front_view(Depth::kMeasured);
  const DepthSurface surface(spec);
  const auto& points = lidar_points(rotations);
  const Pose T_view_body = spec.T_frame_view().inverse();
  for (auto _ : state) benchmark::DoNotOptimize(surface.update(points, T_view_body));
}

void BM_DepthSurfaceWithColumns(benchmark::State& state, int rotations) {
  const ViewSpec spec = front_view(Depth::kMeasured);
  const DepthSurface surface(spec);
  const LidarPoints& l = lidar(rotations);
  const Completion completion = complete_columns(rig(), l.points, l.top, kBodyLidar.translation().cast<float>());
  const Pose T_view_body = spec.T_frame_view().inverse();
  for (auto _ : state) benchmark::DoNotOptimize(surface.update(l.points, T_view_body, nullptr, &completion.points));
}

void BM_DepthMapWithColumns(benchmark::State& state, int rotations) {
  const ViewSpec spec = front_view(Depth::kMeasured);
  const LidarPoints& l = lidar(rotations);
  const Completion completion = complete_columns(rig(), l.points, l.top, kBodyLidar.translation().cast<float>());
  const Pose T_view_body = spec.T_frame_view().inverse();
  const auto view = DepthSurface(spec).update(l.points, T_view_body, nullptr, &completion.points);
  const Occlusion occlusion = view_occlusion(range_images(), *view, l.points, T_view_body, {}, &completion.points);
  for (auto _ : state) {
    benchmark::DoNotOptimize(build_map(rig(), *view, MapPrecision::kAdaptive, Sampling::kFootprint, &occlusion));
  }
}

// The surface on the view's own pixels, as before the lattice (DepthOptions::lattice_cell_deg).
void BM_DepthSurfacePerPixel(benchmark::State& state, int rotations) {
  const ViewSpec spec = front_view(Depth::kMeasured);
  DepthOptions per_pixel;
  per_pixel.lattice_cell_deg = 0;
  const DepthSurface surface(spec, per_pixel);
  const auto& points = lidar_points(rotations);
  const Pose T_view_body = spec.T_frame_view().inverse();
  for (auto _ : state) benchmark::DoNotOptimize(surface.update(points, T_view_body));
}

void BM_DepthOcclusionOnly(benchmark::State& state, int rotations) {
  const ViewSpec spec = front_view(Depth::kMeasured);
  const auto& points = lidar_points(rotations);
  const Pose T_view_body = spec.T_frame_view().inverse();
  const auto view = DepthSurface(spec).update(points, T_view_body);
  for (auto _ : state) benchmark::DoNotOptimize(view_occlusion(range_images(), *view, points, T_view_body));
}

void BM_DepthJudgedOnly(benchmark::State& state, int rotations) {
  const ViewSpec spec = front_view(Depth::kMeasured);
  const auto& points = lidar_points(rotations);
  const auto view = DepthSurface(spec).update(points, spec.T_frame_view().inverse());
  for (auto _ : state) benchmark::DoNotOptimize(view->occlusion_judged());
}

void BM_DepthMapOnly(benchmark::State& state, int rotations, MapPrecision precision, Fusion fusion) {
  ViewSpec spec = front_view(Depth::kMeasured);
  spec.fusion = fusion;
  const auto& points = lidar_points(rotations);
  const Pose T_view_body = spec.T_frame_view().inverse();
  const auto view = DepthSurface(spec).update(points, T_view_body);
  const Occlusion occlusion = view_occlusion(range_images(), *view, points, T_view_body);
  const FeatherSet feathers = feather_set(rig(), spec.feather_px);  // made once per view, as the daemon does
  FusionMap map;
  for (auto _ : state) {
    map = build_map(rig(), *view, precision, Sampling::kFootprint, &occlusion, &feathers);
    benchmark::DoNotOptimize(map);
  }
  size_t two = 0;
  for (const MapEntry& e : map.secondary) two += e.cam != kNoCamera;
  state.counters["two_cameras"] = map.primary.empty() ? 0 : double(two) / double(map.primary.size());
}

// The anchor: the same view on its fixed surface, as the daemon builds it today.
void BM_FixedMapBuild(benchmark::State& state, MapPrecision precision) {
  const auto view = View::create(front_view(Depth::kFixed));
  for (auto _ : state) benchmark::DoNotOptimize(build_map(rig(), *view, precision));
}

}  // namespace

BENCHMARK_CAPTURE(BM_DepthUpdate, vlp16_1_rotation, 1, true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthUpdate, vlp16_10_rotations, 10, true)->Unit(benchmark::kMillisecond)->UseRealTime();
// Without the columns (before stop 41), to see what they cost.
BENCHMARK_CAPTURE(BM_DepthUpdate, vlp16_1_rotation_no_columns, 1, false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthUpdate, vlp16_10_rotations_no_columns, 10, false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ColumnCompletionOnly, vlp16_1_rotation, 1, true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ColumnCompletionOnly, vlp16_1_rotation_no_rays, 1, false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ColumnCompletionOnly, vlp16_10_rotations, 10, true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ColumnCompletionOnly, vlp16_10_rotations_no_rays, 10, false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthSurfaceWithColumns, vlp16_1_rotation, 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthMapWithColumns, vlp16_1_rotation, 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthSurfaceOnly, vlp16_1_rotation, 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthSurfaceOnly, vlp16_10_rotations, 10)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthSurfacePerPixel, vlp16_1_rotation, 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthSurfacePerPixel, vlp16_10_rotations, 10)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthOcclusionOnly, vlp16_1_rotation, 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthOcclusionOnly, vlp16_10_rotations, 10)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthJudgedOnly, vlp16_1_rotation, 1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthMapOnly, vlp16_1_rotation, 1, MapPrecision::kAdaptive, Fusion::kNearestCentre)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthMapOnly, vlp16_1_rotation_exact, 1, MapPrecision::kExact, Fusion::kNearestCentre)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthMapOnly, vlp16_1_rotation_blend, 1, MapPrecision::kAdaptive, Fusion::kBlend)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DepthMapOnly, vlp16_1_rotation_blend_exact, 1, MapPrecision::kExact, Fusion::kBlend)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_FixedMapBuild, adaptive, MapPrecision::kAdaptive)
    ->Name("BM_Anchor_fixed_map_build/front_1024x512")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_FixedMapBuild, exact, MapPrecision::kExact)
    ->Name("BM_Anchor_fixed_map_build_exact/front_1024x512")->Unit(benchmark::kMillisecond)->UseRealTime();

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
