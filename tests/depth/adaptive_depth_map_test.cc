// The adaptive map builder on measured depth with occlusion must agree with the exact one,
// as it does on fixed surfaces (tests/map/adaptive_map_test.cc): the same camera almost
// everywhere, never a picture where the exact map is black (a pixel every camera sees
// hidden) nor black where it has one, coordinates within a fraction of a pixel. On the
// furnished room, from one VLP-16 rotation (rings, gaps, silhouettes) and from the exact
// depth of the scene, for a front, a bird's-eye and a panorama view, on Spot's cameras and
// on a ring of four; nearest-centre and blend.
#include <gtest/gtest.h>

#include <chrono>
#include <iostream>

#include "cloud_scene.h"
#include "core/depth/camera_occluders.h"
#include "core/depth/measured_depth_view.h"
#include "core/synthetic/lidar_scan.h"
#include "depth_scene.h"

namespace omniview {
namespace {

Vec2 decode(const MapEntry& e, int camera_width) {
  return Vec2(e.offset % camera_width + e.fx / 256.0, e.offset / camera_width + e.fy / 256.0);
}

struct Agreement {
  double same_camera = 0;       // share of pixels with the same camera (or both black)
  double painted_over_black = 0;  // share where exact is black and adaptive is not
  double black_over_picture = 0;  // share where adaptive is black and exact is not
  double within_tenth = 0;      // of the same-camera pixels, the share within 0.1 px
  double worst_px = 0;
};

Agreement compare(const Rig& rig, const FusionMap& exact, const FusionMap& adaptive) {
  size_t same = 0, painted = 0, blackened = 0, close = 0, seen_same = 0;
  double worst = 0;
  for (size_t i = 0; i < exact.primary.size(); ++i) {
    const MapEntry& a = exact.primary[i];
    const MapEntry& b = adaptive.primary[i];
    if (a.cam != b.cam) {
      painted += a.cam == kNoCamera;
      blackened += b.cam == kNoCamera;
      continue;
    }
    ++same;
    if (a.cam == kNoCamera) continue;
    ++seen_same;
    const double d = (decode(a, rig.cameras()[a.cam].width) - decode(b, rig.cameras()[a.cam].width)).cwiseAbs().maxCoeff();
    worst = std::max(worst, d);
    close += d <= 0.1;
  }
  const double n = double(exact.primary.size());
  return {double(same) / n, double(painted) / n, double(blackened) / n,
          seen_same ? double(close) / double(seen_same) : 1.0, worst};
}

// Blend maps (the default fusion): where two cameras see a pixel, the adaptive builder
// makes the blend rule's entries exactly, so the second camera and the weights agree but
// for slivers where a camera's region pokes between a block's samples.
// Of the pixels either map has a second camera at, the share where both cameras, their
// coordinates and the weight are the same.
double blend_agreement(const FusionMap& exact, const FusionMap& adaptive) {
  size_t two = 0, same = 0;
  for (size_t i = 0; i < exact.primary.size(); ++i) {
    if (exact.secondary[i].cam == kNoCamera && adaptive.secondary[i].cam == kNoCamera) continue;
    ++two;
    same += exact.secondary[i].cam == adaptive.secondary[i].cam &&
            exact.secondary[i].offset == adaptive.secondary[i].offset &&
            exact.primary[i].cam == adaptive.primary[i].cam && exact.primary[i].offset == adaptive.primary[i].offset &&
            exact.primary_weight[i] == adaptive.primary_weight[i];
  }
  return two ? double(same) / double(two) : 1.0;
}

void expect_agreement(const ViewSpec& fixed_spec, std::shared_ptr<Rig> rig = nullptr, Fusion fusion = Fusion::kNearestCentre) {
  const synthetic::Scene scene = test::furnished_room();
  if (!rig) rig = test::rig_in_world(test::T_world_body());
  ViewSpec spec = fixed_spec;
  spec.depth = Depth::kMeasured;
  spec.fusion = fusion;
  const DepthSurface surface(spec);
  const std::string frame = spec.frame.empty() ? rig->default_frame() : spec.frame;
  const Pose T_world_lidar = test::T_world_body() * test::T_body_lidar();
  const PointCloud scan = synthetic::scan_vlp16(scene, T_world_lidar, "lidar", std::chrono::system_clock::time_point{});
  const Pose T_view_lidar = spec.T_frame_view().inverse() * rig->frames().lookup(frame, "lidar");
  const CameraRangeImages range_images(*rig, ViewOcclusionOptions{}.cell_deg);
  const test::ViewTruth truth = test::view_truth(scene, *rig, fixed_spec);

  struct Input {
    const char* name;
    std::shared_ptr<const MeasuredDepthView> view;
    Occlusion occlusion;
  };
  std::vector<Input> inputs;
  {
    auto view = surface.update(scan.points, T_view_lidar);
    Occlusion o = view_occlusion(range_images, *view, scan.points, T_view_lidar);
    inputs.push_back({"one VLP-16 rotation", view, std::move(o)});
  }
  {
    auto view = surface.update(truth.points, Pose::Identity());
    Occlusion o = view_occlusion(range_images, *view, truth.points, Pose::Identity());
    inputs.push_back({"exact depth", view, std::move(o)});
  }
  for (const Input& in : inputs) {
    const FusionMap exact = build_map(*rig, *in.view, MapPrecision::kExact, Sampling::kBilinear, &in.occlusion);
    const FusionMap adaptive = build_map(*rig, *in.view, MapPrecision::kAdaptive, Sampling::kBilinear, &in.occlusion);
    const Agreement a = compare(*rig, exact, adaptive);
    std::cout << "[ adaptive ] " << spec.name << ", " << in.name << ": same camera " << 100 * a.same_camera
              << " %, painted where exact is black " << 100 * a.painted_over_black << " %, black where exact paints "
              << 100 * a.black_over_picture << " %, within 0.1 px " << 100 * a.within_tenth << " %, worst "
              << a.worst_px << " px\n";
    EXPECT_GE(a.same_camera, 0.995) << spec.name << ", " << in.name;
    EXPECT_LE(a.painted_over_black, 0.001) << spec.name << ", " << in.name;
    EXPECT_LE(a.black_over_picture, 0.001) << spec.name << ", " << in.name;
    // Measured: all within 0.1 px, the worst 0.074 px (the bird's-eye view on one rotation).
    EXPECT_GE(a.within_tenth, 0.999) << spec.name << ", " << in.name;
    EXPECT_LE(a.worst_px, 0.15) << spec.name << ", " << in.name;
    if (fusion == Fusion::kBlend) {
      const double blend = blend_agreement(exact, adaptive);
      std::cout << "[ adaptive ] " << spec.name << ", " << in.name
                << ", blend: of the pixels with a second camera, both entries and the weight the same at "
                << 100 * blend << " %\n";
      EXPECT_GE(blend, 0.999) << spec.name << ", " << in.name;  // measured: 100 % to 6 digits
      EXPECT_EQ(adaptive.camera_used, exact.camera_used) << spec.name << ", " << in.name;
    }
  }
}

TEST(AdaptiveDepthMap, FrontViewAgreesWithExact) { expect_agreement(test::front_spec()); }

TEST(AdaptiveDepthMap, BirdseyeAgreesWithExact) { expect_agreement(test::birdseye_spec()); }

TEST(AdaptiveDepthMap, PanoramaAgreesWithExact) { expect_agreement(test::panorama_spec()); }

TEST(AdaptiveDepthMap, RingOfFourAgreesWithExact) {
  expect_agreement(test::birdseye_spec("ring_birdseye"), test::ring_of_four());
  expect_agreement(test::panorama_spec("ring_panorama"), test::ring_of_four());
}

TEST(AdaptiveDepthMap, BlendAgreesWithExact) {
  expect_agreement(test::front_spec(), nullptr, Fusion::kBlend);
  expect_agreement(test::birdseye_spec(), nullptr, Fusion::kBlend);
  expect_agreement(test::panorama_spec("ring_panorama"), test::ring_of_four(), Fusion::kBlend);
}

}  // namespace
}  // namespace omniview
