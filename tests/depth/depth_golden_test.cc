// Depth-aware views against the truth (issue 32): the Spot-like rig in a furnished room,
// its cameras ray-cast, a bird's-eye, a fused front view and a panorama built four ways: (a) on the
// view's fixed surface, (b) on measured depth from one VLP-16 rotation (completed by columns,
// core/depth/column_completion.h, as the daemon does; also reported without), (c) on the exact
// depth of the scene (a point per view pixel), (d) on the cameras' own depth images alone
// (Spot's stereo depth, 4 m); the truth is what a camera at the view's
// own pose sees. PSNR over the pixels some camera sees; in the bird's-eye view also the
// share of the pixels no camera sees that the view paints anyway.
#include <gtest/gtest.h>

#include <chrono>
#include <iostream>

#include "cloud_scene.h"
#include "core/depth/camera_occluders.h"
#include "core/depth/column_completion.h"
#include "core/depth/measured_depth_view.h"
#include "core/synthetic/lidar_scan.h"
#include "depth_scene.h"

namespace omniview {
namespace {

struct Variants {
  test::DepthScore fixed, lidar, lidar_no_occlusion, lidar_no_columns, exact, exact_no_occlusion;
  test::DepthScore depth_images, depth_images_no_occlusion;  // (d): the cameras' own depth images, no lidar
  double lidar_measured = 0;      // share of the view's pixels on measured depth
  double depth_images_measured = 0;
};

// Spot's `*_depth_in_visual_frame` images as the daemon turns them into points: every 4th
// pixel each way of each camera (spot_adapter/source/image_set.cc's kDepthStep), the scene
// ray-cast up to 4 m along the optical axis (spot-mock's kDepthRangeM); in the view frame.
std::vector<Eigen::Vector3f> depth_image_points(const synthetic::Scene& scene, const Rig& rig, const Pose& T_view_world) {
  constexpr int kStep = 4;
  constexpr double kRangeM = 4.0;
  std::vector<Eigen::Vector3f> points;
  for (size_t i = 0; i < rig.cameras().size(); ++i) {
    const Camera& camera = rig.cameras()[i];
    const Pose T_world_cam = rig.camera_pose("world", i);
    for (int v = kStep / 2; v < camera.height; v += kStep) {
      for (int u = kStep / 2; u < camera.width; u += kStep) {
        Eigen::Vector3d ray;
        if (!unproject(camera.model, Eigen::Vector2d(u, v), ray)) continue;
        const auto hit = scene.intersect(T_world_cam.translation(), T_world_cam.linear() * ray);
        if (!hit || (T_world_cam.inverse() * hit->point).z() > kRangeM) continue;
        points.push_back((T_view_world * hit->point).cast<float>());
      }
    }
  }
  return points;
}

std::vector<Eigen::Vector3f> moved(const std::vector<Eigen::Vector3f>& points, const Pose& T) {
  std::vector<Eigen::Vector3f> out;
  out.reserve(points.size());
  for (const auto& p : points) out.push_back((T * p.cast<double>()).cast<float>());
  return out;
}

void report(const std::string& what, const Variants& r) {
  const auto line = [&](const char* name, const test::DepthScore& s) {
    std::cout << "[ depth  ] " << what << " " << name << ": PSNR " << s.psnr_db << " dB over " << s.seen
              << " seen px; unseen painted " << 100 * s.unseen_painted << " % of " << s.unseen << "\n";
  };
  line("(a) fixed surface      ", r.fixed);
  line("(b) one VLP-16 rotation", r.lidar);
  line("    (b) without occlusion", r.lidar_no_occlusion);
  line("    (b) without columns", r.lidar_no_columns);
  line("(c) exact depth        ", r.exact);
  line("    (c) without occlusion", r.exact_no_occlusion);
  line("(d) depth images only  ", r.depth_images);
  line("    (d) without occlusion", r.depth_images_no_occlusion);
  std::cout << "[ depth  ] " << what << ": " << 100 * r.lidar_measured << " % of pixels on measured depth (b), "
            << 100 * r.depth_images_measured << " % (d)\n";
}

Variants run(const ViewSpec& fixed_spec, std::shared_ptr<Rig> rig = nullptr) {
  const synthetic::Scene scene = test::furnished_room();
  if (!rig) rig = test::rig_in_world(test::T_world_body());
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
  // In the robot frame with the columns that complete them (column_completion.h), as the
  // daemon's geometry makes them: open tops on the lidar's top ring, its rays from its place.
  const Pose T_robot_lidar = rig->frames().lookup(rig->default_frame(), "lidar");
  const Pose T_view_robot = T_frame_view.inverse() * rig->frames().lookup(frame, rig->default_frame());
  const std::vector<Eigen::Vector3f> lidar_points = moved(scan.points, T_robot_lidar);
  const Completion lidar_columns = complete_columns(*rig, lidar_points, lidar_flags(scan.points),
                                                    T_robot_lidar.translation().cast<float>());
  DepthStats stats;
  const auto lidar_view = surface.update(lidar_points, T_view_robot, &stats, &lidar_columns.points);
  r.lidar_measured = lidar_view->measured_fraction();
  const CameraRangeImages range_images(*rig, ViewOcclusionOptions{}.cell_deg);
  const Occlusion lidar_occlusion =
      view_occlusion(range_images, *lidar_view, lidar_points, T_view_robot, {}, &lidar_columns.points);
  r.lidar = test::score(build_map(*rig, *lidar_view, MapPrecision::kAdaptive, Sampling::kBilinear, &lidar_occlusion),
                        images, truth);
  const auto uncompleted_view = surface.update(lidar_points, T_view_robot);
  const Occlusion uncompleted_occlusion = view_occlusion(range_images, *uncompleted_view, lidar_points, T_view_robot);
  r.lidar_no_columns = test::score(
      build_map(*rig, *uncompleted_view, MapPrecision::kAdaptive, Sampling::kBilinear, &uncompleted_occlusion), images,
      truth);
  r.lidar_no_occlusion = test::score(build_map(*rig, *lidar_view, MapPrecision::kExact, Sampling::kBilinear), images,
                                     truth);
  std::cout << "[ depth  ] lidar: " << stats.points << " points, " << stats.outside_view << " outside the view, "
            << stats.splatted_pixels << " px splatted, " << stats.filled_pixels << " filled, " << stats.see_through
            << " seen through; columns: ground at " << lidar_columns.ground_z.value_or(NAN) << " m, "
            << lidar_columns.stats.columns << " columns (" << lidar_columns.stats.open_tops << " open-topped, " << lidar_columns.stats.overhead << " overhead), " << lidar_columns.stats.top_points << " joining tops, "
            << lidar_columns.points.size() << " points added, " << stats.completed_pixels << " px completed\n";

  // (c) The exact depth: the truth's own hit points for the surface; for the occluders also
  // the scene sampled densely from the lidar's place (0.25 deg steps, -70 .. +30 deg), which
  // holds the sides of things the view does not see but the cameras do.
  std::vector<Eigen::Vector3f> dense = truth.points;
  const Pose T_view_world = T_view_lidar * T_world_lidar.inverse();
  for (double el = -70; el <= 30; el += 0.25) {
    for (double az = 0; az < 360; az += 0.25) {
      const double e = el * M_PI / 180, a = az * M_PI / 180;
      const Vec3 dir(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      const auto hit = scene.intersect(T_world_lidar.translation(), T_world_lidar.linear() * dir);
      if (hit) dense.push_back((T_view_world * hit->point).cast<float>());
    }
  }
  const auto exact_view = surface.update(truth.points, Pose::Identity());
  const Occlusion exact_occlusion = view_occlusion(range_images, *exact_view, dense, Pose::Identity());
  r.exact = test::score(build_map(*rig, *exact_view, MapPrecision::kAdaptive, Sampling::kBilinear, &exact_occlusion),
                        images, truth);
  r.exact_no_occlusion = test::score(build_map(*rig, *exact_view, MapPrecision::kExact, Sampling::kBilinear), images,
                                     truth);

  // (d) The body cameras' depth images alone (Spot's stereo, ~4 m), no lidar.
  const std::vector<Eigen::Vector3f> from_images = depth_image_points(scene, *rig, T_view_world);
  const Completion image_columns = complete_columns(*rig, moved(from_images, T_view_robot.inverse()), {}, std::nullopt);
  const std::vector<Eigen::Vector3f> image_completion = moved(image_columns.points, T_view_robot);
  const auto images_view = surface.update(from_images, Pose::Identity(), nullptr, &image_completion);
  r.depth_images_measured = images_view->measured_fraction();
  const Occlusion images_occlusion =
      view_occlusion(range_images, *images_view, from_images, Pose::Identity(), {}, &image_completion);
  r.depth_images = test::score(
      build_map(*rig, *images_view, MapPrecision::kAdaptive, Sampling::kBilinear, &images_occlusion), images, truth);
  r.depth_images_no_occlusion =
      test::score(build_map(*rig, *images_view, MapPrecision::kExact, Sampling::kBilinear), images, truth);
  return r;
}

TEST(DepthGolden, BirdseyeOnMeasuredDepth) {
  const ViewSpec v = test::birdseye_spec();
  const Variants r = run(v);
  report("bird's-eye", r);
  // Measured (release, stop 39; issue targets in brackets):
  //   (a) fixed ground              30.8 dB, unseen painted 76.7 %
  //   (b) one VLP-16 rotation       30.8 dB, 44.1 %  (31.7 dB, 71.9 % without occlusion;
  //                                 31.0 dB, 59.1 % without columns)
  //   (c) exact depth of the scene  42.7 dB,  4.3 %  (35.5 dB, 54.3 % without occlusion)
  //   (d) depth images only         27.8 dB, 27.0 %  (31.1 dB, 76.6 % without occlusion)
  // With the exact depth the targets hold (>= fixed + 6 dB: +11.8; <= 5 % painted). With
  // one rotation they do not (>= fixed + 6 dB, within 2 dB of (c), <= 5 %): its rings
  // leave the pillars' and boxes' lower and upper parts unmeasured, the floor behind them
  // stays the fixed ground, which the cameras see those objects over (painted), and the
  // lidar's samples at silhouettes, seen from the cameras' places, blacken some visible
  // floor (without occlusion it beats the ground by 0.7 dB, but paints what no camera
  // sees). These bounds guard what works, below the figures by compiler-noise margins.
  // (Rings joined in two passes and occlusion judged 3 px inside the measured surface, stop
  // 32: (b) 27.1 -> 27.5 dB. Not judged within 2 deg of a nearer surface where the depth is
  // mostly filled in, stop 38: (b) 27.5 -> 29.9 dB, unseen painted 57.2 -> 58.8 %; (c)
  // unchanged. Maps adaptive since stop 38: (c) 42.7 dB, 4.3 %. The cameras' occluders from
  // the measured points alone, not also the view's filled surface, stop 39: (b) 29.9 ->
  // 31.0 dB, (d) 26.2 -> 27.8 dB.)
  // Depth images alone (d) see everything within 4 m of each camera, so occlusion takes the
  // unseen pixels painted from 77 % to 28 %; but it costs 3.3 dB over the seen ones: where
  // one camera's depth ends behind an object, its range image is filled across to what
  // another camera measured beyond, and floor that camera does see is judged hidden. Not
  // met here: >= fixed + 6 dB, <= 5 % painted.
  EXPECT_GE(r.exact.psnr_db, r.fixed.psnr_db + 10);
  EXPECT_GT(r.exact.psnr_db, r.exact_no_occlusion.psnr_db + 5);  // occlusion helps where the geometry is whole
  EXPECT_LE(r.exact.unseen_painted, 0.06);
  // Columns (stop 41): the objects' sides whole from the floor up, as occluders too: the
  // unseen pixels painted 59.1 -> 44.1 %, for 0.2 dB (31.0 -> 30.8 dB; box tops between
  // rings, which no column makes, now read as floor hidden inside the box).
  EXPECT_LT(r.lidar.unseen_painted, r.fixed.unseen_painted - 0.3);
  EXPECT_LT(r.lidar.unseen_painted, r.lidar_no_columns.unseen_painted - 0.1);
  EXPECT_GT(r.lidar.psnr_db, r.fixed.psnr_db - 0.8);
  EXPECT_GT(r.lidar_no_occlusion.psnr_db, r.fixed.psnr_db);
  // Stop 42: closed tops joined across the cells the rings or the depth images' samples
  // skipped (core/depth/flat_tops.h), columns standing at their cell's mean place and taken
  // as vertical stretches in the view and the cameras' occluders (range_splat.h): (b)
  // 30.8 -> 30.5 dB with the unseen pixels painted 44.1 -> 30.6 % (the occluders now whole
  // between the columns); (d) 27.8 -> 28.9 dB, 27.1 -> 27.5 %. Half of (b)'s error is the
  // low crate's top beside the robot, which the cameras see only at 1 deg grazing (they
  // stand 3 cm above it: a centimetre off in its height moves its picture by decimetres,
  // and its own occluders hide it); the exact depth alone gets it right.
  EXPECT_LT(r.lidar.unseen_painted, 0.35);
  EXPECT_LT(r.depth_images.unseen_painted, r.fixed.unseen_painted - 0.4);
  EXPECT_GT(r.depth_images.psnr_db, r.fixed.psnr_db - 3);
}

TEST(DepthGolden, FrontViewOnMeasuredDepth) {
  const ViewSpec v = test::front_spec();
  const Variants r = run(v);
  report("front", r);
  // Measured (release, this commit):
  //   (a) fixed plane, floor cut in 40.9 dB
  //   (b) one VLP-16 rotation       30.1 dB (43.7 dB without occlusion; one pass of the
  //                                 gap fill and occlusion to the surface's edge: 28.8, 42.3)
  //   (c) exact depth of the scene  48.2 dB, unseen painted 37 % (48.2 dB, 100 % without)
  //   (d) depth images only         47.5 dB (+6.5 dB; 0.8 dB below (c): within the 2;
  //                                 46.6 without columns)
  // Columns (stop 41): one rotation 43.7 -> 44.5 dB (the crate's and pillars' feet below the
  // lowest ring stand on them, not on the floor behind). Stop 42: 44.5 -> 46.5 dB, 1.7 dB
  // below (c): the "within 2 dB of exact" met for one rotation too. The columns
  // stood at one point of each cell, 5 and 10 cm apart by turns on the crate's face, and
  // their points, a few pixels apart both ways and off the view's rows, left rectangles
  // of the fixed plane 3 m behind the face (44.5 -> 45.4 dB at each cell's mean place,
  // -> 46.5 dB as vertical stretches).
  // On this smooth texture the fixed plane with the floor is already close. Exact depth
  // gains 7.3 dB (target >= 6: met); one rotation gains 2.8 dB, with occlusion as without
  // it since stop 38 (43.7 dB; target +6 not met). Before, with occlusion it lost 11 dB
  // (30.1 dB): the cameras judged pixels along objects' side edges hidden (dots of black)
  // where the lidar leaves the edge uncertain (MeasuredDepthView::occlusion_judged).
  EXPECT_GE(r.exact.psnr_db, r.fixed.psnr_db + 6);
  EXPECT_GE(r.exact.psnr_db, r.exact_no_occlusion.psnr_db - 0.5);  // no visible pixel blackened
  EXPECT_LE(r.exact.unseen_painted, 0.45);
  EXPECT_GE(r.lidar_no_occlusion.psnr_db, r.fixed.psnr_db + 2.3);
  EXPECT_GE(r.lidar.psnr_db, r.fixed.psnr_db + 3.2);
  EXPECT_GE(r.lidar.psnr_db, r.lidar_no_columns.psnr_db + 2);
  EXPECT_GE(r.lidar.psnr_db, r.exact.psnr_db - 2);
  EXPECT_GE(r.lidar.psnr_db, r.lidar_no_occlusion.psnr_db - 0.5);  // occlusion blackens no visible edge
  EXPECT_GE(r.depth_images.psnr_db, r.fixed.psnr_db + 6);
  EXPECT_GE(r.depth_images.psnr_db, r.exact.psnr_db - 2);
}

// A view larger than the goldens' is made on the lattice (DepthOptions::lattice_cell_deg:
// the goldens' own pixels are coarser than a cell, so above it is not): the front view at
// 1024 x 512 (2 x 2 pixels a cell), one rotation and the depth images, with occlusion, on the
// lattice and on the view's own pixels.
TEST(DepthGolden, ALargeViewOnTheLatticeDoesAsWellAsOnItsPixels) {
  ViewSpec spec = test::front_spec();
  spec.width = 1024;
  spec.height = 512;
  const synthetic::Scene scene = test::furnished_room();
  const auto rig = test::rig_in_world(test::T_world_body());
  const std::vector<cv::Mat> images = test::render_images(scene, *rig, /*grey=*/true);
  const test::ViewTruth truth = test::view_truth(scene, *rig, spec);
  spec.depth = Depth::kMeasured;
  const Pose T_world_lidar = test::T_world_body() * test::T_body_lidar();
  const PointCloud scan = synthetic::scan_vlp16(scene, T_world_lidar, "lidar", std::chrono::system_clock::time_point{});
  const Pose T_view_lidar = spec.T_frame_view().inverse() * rig->frames().lookup(rig->default_frame(), "lidar");
  const std::vector<Eigen::Vector3f> from_images =
      depth_image_points(scene, *rig, T_view_lidar * T_world_lidar.inverse());
  const CameraRangeImages range_images(*rig, ViewOcclusionOptions{}.cell_deg);
  const auto psnr = [&](const DepthSurface& surface, const std::vector<Eigen::Vector3f>& points, const Pose& T) {
    const auto view = surface.update(points, T);
    const Occlusion occlusion = view_occlusion(range_images, *view, points, T);
    return test::score(build_map(*rig, *view, MapPrecision::kAdaptive, Sampling::kBilinear, &occlusion), images, truth)
        .psnr_db;
  };
  const DepthSurface on_lattice(spec);
  DepthOptions per_pixel;
  per_pixel.lattice_cell_deg = 0;
  const DepthSurface on_pixels(spec, per_pixel);
  ASSERT_EQ(on_lattice.lattice().cell, 2);
  const double lidar_lattice = psnr(on_lattice, scan.points, T_view_lidar);
  const double lidar_pixels = psnr(on_pixels, scan.points, T_view_lidar);
  const double images_lattice = psnr(on_lattice, from_images, Pose::Identity());
  const double images_pixels = psnr(on_pixels, from_images, Pose::Identity());
  std::cout << "[ depth  ] front 1024x512, one rotation: " << lidar_lattice << " dB on the lattice, " << lidar_pixels
            << " dB per pixel; depth images: " << images_lattice << " / " << images_pixels << " dB\n";
  // Measured (release, stop 40): one rotation 43.7 / 42.3 dB, depth images 46.4 / 46.3 dB.
  EXPECT_GE(lidar_lattice, lidar_pixels - 0.3);
  EXPECT_GE(images_lattice, images_pixels - 0.3);
}

TEST(DepthGolden, PanoramaOnMeasuredDepth) {
  // A 360 deg panorama at the body's centre, its sphere 3 m out and the floor cut in.
  const ViewSpec v = test::panorama_spec();
  const Variants r = run(v);
  report("panorama", r);
  // Measured (release, stop 38):
  //   (a) fixed sphere, floor cut in  25.1 dB, unseen painted 4.6 %
  //   (b) one VLP-16 rotation         32.3 dB, 3.8 %  (32.1 dB, 3.9 % without occlusion)
  //   (c) exact depth of the scene    46.8 dB, 0.5 %  (40.9 dB, 3.8 % without occlusion)
  //   (d) depth images only           27.2 dB, 4.4 %  (the walls past 5 m are beyond their 4 m:
  //                                   on the fixed sphere, as (a))
  // All around the robot the objects stand well off the 3 m sphere, so measured depth
  // pays most here: one rotation meets the issue's +6 dB (+7.2); within 2 dB of (c) it
  // does not (the rings leave the objects' tops and bottoms unmeasured).
  // Columns (stop 41): one rotation 32.2 -> 37.1 dB (+12.0 over the fixed sphere; the walls
  // and pillars past the top ring and the feet below the lowest one stand on them), depth
  // images 27.2 -> 27.9 dB. Still 9.7 dB below (c): the walls above the columns' 8 deg.
  // Stop 42 (columns as stretches, joined tops): one rotation 37.1 -> 37.6 dB.
  EXPECT_GE(r.lidar.psnr_db, r.fixed.psnr_db + 11);
  EXPECT_GE(r.lidar.psnr_db, r.lidar_no_columns.psnr_db + 4);
  EXPECT_GE(r.exact.psnr_db, r.fixed.psnr_db + 15);
  EXPECT_GT(r.exact.psnr_db, r.exact_no_occlusion.psnr_db + 4.5);
  EXPECT_LE(r.lidar.unseen_painted, r.fixed.unseen_painted);
  EXPECT_LE(r.exact.unseen_painted, 0.01);
  EXPECT_GE(r.depth_images.psnr_db, r.fixed.psnr_db + 1.5);
}

TEST(DepthGolden, RingOfFourCameras) {
  const ViewSpec birdseye = test::birdseye_spec("ring_birdseye");
  const Variants b = run(birdseye, test::ring_of_four());
  report("ring, bird's-eye", b);
  const ViewSpec panorama = test::panorama_spec("ring_panorama");
  const Variants p = run(panorama, test::ring_of_four());
  report("ring, panorama", p);
  // Measured (release, stop 38):
  //   bird's-eye: (a) fixed ground 29.5 dB, unseen painted 94.9 %; (b) one rotation 32.0 dB,
  //   49.9 % (30.8 dB, 92.3 % without occlusion); (c) exact depth 40.5 dB, 6.4 %.
  //   panorama: (a) fixed sphere 23.5 dB; (b) 27.7 dB; (c) 48.5 dB (46.3 without occlusion).
  //   Depth images only (d), stop 39: bird's-eye 33.1 dB, 34.7 % painted; panorama 28.3 dB.
  // The ring stands its cameras 0.3 m out, so parallax against the fixed surfaces is worse
  // than Spot's and measured depth gains more in the bird's-eye view; exact depth meets the
  // issue's +6 dB in both, one rotation does not (+2.3, +4.2 dB: the rings leave the
  // objects' tops, bottoms and the floor behind them unmeasured).
  EXPECT_GE(b.exact.psnr_db, b.fixed.psnr_db + 9);
  // Columns (stop 41): bird's-eye one rotation 32.0 -> 30.6 dB, 49.9 -> 38.4 % of the
  // unseen pixels painted (as Spot's bird's-eye: box tops between rings read as floor
  // hidden inside the box); panorama 27.7 -> 37.7 dB; depth images: panorama 28.3 -> 31.2 dB,
  // bird's-eye 33.1 dB as before. Stop 42 (columns as stretches in the view and the
  // occluders, joined tops): bird's-eye 30.6 -> 30.2 dB, 38.4 -> 35.7 % painted (the
  // cameras 10 cm above the low crate's top see it at 3.6 deg grazing: its error tripled);
  // panorama 37.7 -> 38.3 dB.
  EXPECT_GE(b.lidar.psnr_db, b.fixed.psnr_db + 0.4);
  EXPECT_LE(b.lidar.unseen_painted, b.fixed.unseen_painted - 0.5);
  EXPECT_GE(p.lidar.psnr_db, p.lidar_no_columns.psnr_db + 8);
  EXPECT_LE(b.exact.unseen_painted, 0.08);
  EXPECT_GE(p.exact.psnr_db, p.fixed.psnr_db + 20);
  EXPECT_GE(p.lidar.psnr_db, p.fixed.psnr_db + 12);
  EXPECT_GE(b.depth_images.psnr_db, b.fixed.psnr_db + 3);
  EXPECT_LE(b.depth_images.unseen_painted, b.fixed.unseen_painted - 0.5);
  EXPECT_GE(p.depth_images.psnr_db, p.fixed.psnr_db + 6.5);
}

}  // namespace
}  // namespace omniview
