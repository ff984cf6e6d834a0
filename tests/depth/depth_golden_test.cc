// Depth-aware views against the truth (issue 32): the Spot-like rig in a furnished room,
// its cameras ray-cast, a bird's-eye and a fused front view built three ways: (a) on the
// view's fixed surface, (b) on measured depth from one VLP-16 rotation, (c) on the exact
// depth of the scene (a point per view pixel); the truth is what a camera at the view's
// own pose sees. PSNR over the pixels some camera sees; in the bird's-eye view also the
// share of the pixels no camera sees that the view paints anyway.
#include <gtest/gtest.h>

#include <chrono>
#include <iostream>

#include "cloud_scene.h"
#include "core/depth/camera_occluders.h"
#include "core/depth/measured_depth_view.h"
#include "core/synthetic/lidar_scan.h"
#include "depth_scene.h"
#include "core/camera/camera_model.h"

namespace omniview {
namespace {

struct Variants {
  test::DepthScore fixed, lidar, lidar_no_occlusion, exact, exact_no_occlusion;
  double lidar_measured = 0;  // share of the view's pixels on measured depth
};

void report(const std::string& what, const Variants& r) {
  const auto line = [&](const char* name, const test::DepthScore& s) {
    std::cout << "[ depth  ] " << what << " " << name << ": PSNR " << s.psnr_db << " dB over " << s.seen
              << " seen px; unseen painted " << 100 * s.unseen_painted << " % of " << s.unseen << "\n";
  };
  line("(a) fixed surface      ", r.fixed);
  line("(b) one VLP-16 rotation", r.lidar);
  line("    (b) without occlusion", r.lidar_no_occlusion);
  line("(c) exact depth        ", r.exact);
  line("    (c) without occlusion", r.exact_no_occlusion);
  std::cout << "[ depth  ] " << what << ": " << 100 * r.lidar_measured << " % of pixels on measured depth (b)\n";
}

ColourOptions occlusion_options() {
  ColourOptions o;
  if (const char* e = std::getenv("CELL")) o.occlusion_cell_deg = std::atof(e);
  if (const char* e = std::getenv("REACH")) o.occlusion_reach_deg = std::atof(e);
  if (const char* e = std::getenv("TOL")) o.occlusion_tolerance_rel = std::atof(e);
  return o;
}

Variants run(const ViewSpec& fixed_spec) {
  const synthetic::Scene scene = test::furnished_room();
  const auto rig = test::rig_in_world(test::T_world_body());
  const std::vector<cv::Mat> images = test::render_images(scene, *rig, /*grey=*/true);
  const test::ViewTruth truth = test::view_truth(scene, *rig, fixed_spec);
  Variants r;
  r.fixed = test::score(build_map(*rig, *View::create(fixed_spec), MapPrecision::kAdaptive, Sampling::kBilinear),
                        images, truth);

  ViewSpec spec = fixed_spec;
  spec.depth = Depth::kMeasured;
  const DepthSurface surface(spec);
  const std::string frame = spec.frame.empty() ? rig->default_frame() : spec.frame;
  const Pose T_frame_view = spec.T_frame_view();

  // (b) One rotation of the lidar on the body's back, points in its frame.
  const Pose T_world_lidar = test::T_world_body() * test::T_body_lidar();
  const PointCloud scan = synthetic::scan_vlp16(scene, T_world_lidar, "lidar", std::chrono::system_clock::time_point{});
  const Pose T_view_lidar = T_frame_view.inverse() * rig->frames().lookup(frame, "lidar");
  DepthStats stats;
  const auto lidar_view = surface.update(scan.points, T_view_lidar, &stats);
  r.lidar_measured = lidar_view->measured_fraction();
  const Occlusion lidar_occlusion = view_occlusion(*rig, *lidar_view, scan.points, T_view_lidar, occlusion_options());
  r.lidar = test::score(build_map(*rig, *lidar_view, MapPrecision::kExact, Sampling::kBilinear, &lidar_occlusion),
                        images, truth);
  r.lidar_no_occlusion = test::score(build_map(*rig, *lidar_view, MapPrecision::kExact, Sampling::kBilinear), images,
                                     truth);
  std::cout << "[ depth  ] lidar: " << stats.points << " points, " << stats.outside_view << " outside the view, "
            << stats.splatted_pixels << " px splatted, " << stats.filled_pixels << " filled, " << stats.see_through
            << " seen through\n";

  // (c) The exact depth: the truth's own hit points, also standing in for the occluders.
  const auto exact_view = surface.update(truth.points, Pose::Identity());
  const Occlusion exact_occlusion = view_occlusion(*rig, *exact_view, truth.points, Pose::Identity(), occlusion_options());
  r.exact = test::score(build_map(*rig, *exact_view, MapPrecision::kExact, Sampling::kBilinear, &exact_occlusion),
                        images, truth);
  r.exact_no_occlusion = test::score(build_map(*rig, *exact_view, MapPrecision::kExact, Sampling::kBilinear), images,
                                     truth);
  return r;
}

TEST(DepthGolden, BirdseyeOnMeasuredDepth) {
  ViewSpec v;
  v.name = "birdseye";
  v.type = ViewType::kBirdseye;
  v.width = v.height = 400;
  v.pitch_deg = 90;
  v.height_m = 4;
  v.ground_z = -0.5;  // the floor, in the body frame
  v.hfov_deg = 100;
  const Variants r = run(v);
  report("bird's-eye", r);
  EXPECT_GE(r.lidar.psnr_db, r.fixed.psnr_db + 6);
  EXPECT_GE(r.lidar.psnr_db, r.exact.psnr_db - 2);
  EXPECT_LE(r.lidar.unseen_painted, 0.05);
}

TEST(DepthGolden, FrontViewOnMeasuredDepth) {
  // As config/spot.yaml's front view: at the front cameras, pitched down, the floor cut in.
  ViewSpec v;
  v.name = "front";
  v.type = ViewType::kPerspective;
  v.width = 512;
  v.height = 256;
  v.position = Vec3(0.42, 0, 0.02);
  v.pitch_deg = 27;
  v.hfov_deg = 100;
  v.distance = 3;
  v.ground = true;
  v.ground_z = -0.5;
  const Variants r = run(v);
  report("front", r);
  EXPECT_GE(r.lidar.psnr_db, r.fixed.psnr_db + 6);
  EXPECT_GE(r.lidar.psnr_db, r.exact.psnr_db - 2);
}

}  // namespace
}  // namespace omniview
