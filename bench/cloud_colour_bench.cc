// Colouring lidar clouds from Spot's five body cameras (the Spot-like rig, 640x480 each):
// one VLP-16 rotation (~28.8 k points) and a 300 k-point cloud, with occlusion, against the
// reference method restated in the same run (per point, per camera, double precision,
// nearest-centre, no occlusion: what Oehler & von Stryk's framework does; their paper
// reports 57.7 ms for one VLP-16 cloud). Run: see bench/README.md.
#include <benchmark/benchmark.h>

#include <chrono>
#include <limits>

#include <opencv2/core/utility.hpp>

#include "core/cloud/colourer.h"
#include "core/cloud/vlp16.h"
#include "core/synthetic/lidar_scan.h"
#include "core/synthetic/render.h"
#include "core/synthetic/spot_like_rig.h"

namespace omniview {
namespace {

struct World {
  std::shared_ptr<Rig> rig;
  CameraImages images;
  PointCloud rotation;  // one VLP-16 rotation
  PointCloud large;     // ~300 k points
};

const World& world() {
  static const World w = [] {
    World w;
    synthetic::Scene scene;
    scene.add(synthetic::Box{Vec3(-4.5, -3.5, 0), Vec3(4.5, 3.5, 3)});
    scene.add(synthetic::Box{Vec3(1.7, -0.2, 0), Vec3(1.9, 0.1, 2.5)});  // a post: occlusion has work to do
    const Pose T_world_body = make_pose(Vec3(0.4, -0.3, 0.55), 0.3, 0, 0);
    const Pose T_body_lidar = make_pose(Vec3(-0.1, 0, 0.3), 0, 0, 0);
    w.rig = std::make_shared<Rig>(synthetic::spot_like_rig());
    w.rig->add_frame("lidar", "body", T_body_lidar);
    w.rig->add_frame("world", "body", T_world_body.inverse());
    synthetic::RenderOptions render;
    render.supersample = 1;
    for (size_t i = 0; i < w.rig->cameras().size(); ++i) {
      w.images.images.push_back(synthetic::render_camera(scene, *w.rig, i, "world", render));
    }
    const auto stamp = std::chrono::system_clock::now();
    w.rotation = synthetic::scan_vlp16(scene, T_world_body * T_body_lidar, "lidar", stamp);
    synthetic::LidarScanOptions dense;
    dense.columns = 18750;  // 16 x 18750 = 300 k rays
    w.large = synthetic::scan_vlp16(scene, T_world_body * T_body_lidar, "lidar", stamp, dense);
    return w;
  }();
  return w;
}

void BM_Colour(benchmark::State& state, bool large, bool occlusion, Fusion fusion) {
  const World& w = world();
  // Arg: OpenCV's pool size. With 1 thread the CPU column is the whole cost; with 2 (this
  // box's cores) the real-time column is what a cloud waits.
  cv::setNumThreads(static_cast<int>(state.range(0)));
  PointCloud cloud = large ? w.large : w.rotation;
  CloudColourer colourer(w.rig);
  ColourOptions options;
  options.occlusion = occlusion;
  options.fusion = fusion;
  ColourStats stats;
  for (auto _ : state) {
    stats = colourer.colour(cloud, w.images, options);
    benchmark::DoNotOptimize(cloud.rgb.data());
  }
  state.counters["points"] = static_cast<double>(cloud.size());
  state.counters["coloured"] = static_cast<double>(stats.coloured);
  state.counters["occluded"] = static_cast<double>(stats.occluded);
  cv::setNumThreads(-1);
}

// The reference method restated: for each point, for each camera, transform in double,
// project through the model (a virtual-style dispatch per call), keep the camera whose
// pixel is nearest its image centre, then sample that camera's pixel. No occlusion.
void BM_Anchor_reference(benchmark::State& state, bool large) {
  const World& w = world();
  const PointCloud& input = large ? w.large : w.rotation;
  const Rig& rig = *w.rig;
  std::vector<Pose> T_cam_cloud;
  for (size_t c = 0; c < rig.cameras().size(); ++c) {
    T_cam_cloud.push_back(rig.camera_pose(rig.default_frame(), c).inverse() * rig.frames().lookup(rig.default_frame(), input.frame));
  }
  std::vector<PointCloud::Rgb> rgb(input.size());
  for (auto _ : state) {
    for (size_t i = 0; i < input.size(); ++i) {
      const Vec3 p = input.points[i].cast<double>();
      double best = std::numeric_limits<double>::max();
      int best_cam = -1;
      Vec2 best_uv;
      for (size_t c = 0; c < rig.cameras().size(); ++c) {
        const Camera& cam = rig.cameras()[c];
        Vec2 uv;
        if (!project(cam.model, T_cam_cloud[c] * p, uv) || !cam.in_image(uv.x(), uv.y())) continue;
        if (!cam.mask.empty() && cam.mask.at<uint8_t>(int(uv.y() + 0.5), int(uv.x() + 0.5)) <= 127) continue;
        const double du = uv.x() - (cam.width - 1) / 2.0, dv = uv.y() - (cam.height - 1) / 2.0;
        const double d = du * du + dv * dv;
        if (d < best) {
          best = d;
          best_cam = static_cast<int>(c);
          best_uv = uv;
        }
      }
      if (best_cam >= 0) {
        const cv::Vec3b bgr = w.images.images[best_cam].at<cv::Vec3b>(int(best_uv.y() + 0.5), int(best_uv.x() + 0.5));
        rgb[i] = {bgr[2], bgr[1], bgr[0]};
      }
    }
    benchmark::DoNotOptimize(rgb.data());
  }
  state.counters["points"] = static_cast<double>(input.size());
}

// VLP-16 decoding: the packets of one rotation (0.1 s of data at 10 Hz) into a cloud.
// Real time is 100 ms: the "x_real_time" counter says how many times faster we decode.
void BM_Vlp16DecodeRotation(benchmark::State& state) {
  // Packets like the sensor's, with every return 5-20 m away.
  constexpr int kPackets = 76;  // 100 ms / (12 x 110.592 us)
  std::vector<std::vector<uint8_t>> packets(kPackets, std::vector<uint8_t>(kVlp16PacketSize, 0));
  for (int k = 0; k < kPackets; ++k) {
    auto& p = packets[k];
    for (int b = 0; b < 12; ++b) {
      const int az = static_cast<int>(std::lround((12 * k + b) * 39.813)) % 36000;
      p[100 * b] = 0xFF;
      p[100 * b + 1] = 0xEE;
      p[100 * b + 2] = static_cast<uint8_t>(az);
      p[100 * b + 3] = static_cast<uint8_t>(az >> 8);
      for (int c = 0; c < 32; ++c) {
        const int d = 2500 + (k * 37 + b * 11 + c * 101) % 7500;
        p[100 * b + 4 + 3 * c] = static_cast<uint8_t>(d);
        p[100 * b + 5 + 3 * c] = static_cast<uint8_t>(d >> 8);
      }
    }
    p[1204] = 0x37;
  }
  Vlp16Assembler assembler(Vlp16Calibration{}, "velodyne");
  const auto now = std::chrono::system_clock::now();
  size_t points = 0;
  for (auto _ : state) {
    for (const auto& p : packets) {
      for (const auto& cloud : assembler.add_packet(p.data(), p.size(), now)) points = cloud.size();
    }
  }
  state.counters["points"] = static_cast<double>(points);
  state.counters["x_real_time"] = benchmark::Counter(0.1 * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Vlp16DecodeRotation)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_CAPTURE(BM_Colour, vlp16_rotation_occlusion_nearest, false, true, Fusion::kNearestCentre)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Colour, vlp16_rotation_no_occlusion_nearest, false, false, Fusion::kNearestCentre)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Colour, vlp16_rotation_occlusion_blend, false, true, Fusion::kBlend)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Colour, cloud_300k_occlusion_nearest, true, true, Fusion::kNearestCentre)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Anchor_reference, vlp16_rotation, false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Anchor_reference, cloud_300k, true)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace omniview

BENCHMARK_MAIN();
