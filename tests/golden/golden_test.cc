// Golden scenes: each view type, camera model and fusion policy against the texture of a
// scene that coincides with the view's projection surface.
//
// Thresholds. The camera images are rendered with 3x3 supersampling and stored in 8 bits;
// the view then resamples them bilinearly, which low-passes the texture a little where a
// camera pixel covers more of the surface than a view pixel does. Measured PSNRs for
// correct geometry range from 35 dB (Spot's floor, seen at grazing angles where the
// texture is finer than a camera pixel) to 54 dB (the test output prints each). So each
// test has its own bound, 4 dB below what it measured: room for compiler and library
// differences, not for a pixel of misregistration, which costs 13 dB here (see
// OnePixelOfCalibrationErrorFailsTheBound); the naive stitch of the paper's Fig. 4 costs 35.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/golden/golden.h"

namespace omniview {
namespace {

using synthetic::Cylinder;
using synthetic::Plane;
using synthetic::Scene;
using synthetic::Sphere;

constexpr double kDualFisheyeBoundDb = 49;  // measured 53.4

ViewSpec view(ViewType type, int w, int h) {
  ViewSpec s;
  s.name = to_string(type);
  s.type = type;
  s.width = w;
  s.height = h;
  return s;
}

Camera camera(const std::string& name, CameraModel model, int w, int h, const Vec3& xyz, double yaw, double pitch,
              double roll, double fov_deg = 0) {
  Camera c;
  c.name = name;
  c.model = std::move(model);
  c.width = w;
  c.height = h;
  c.fov_deg = fov_deg;
  const double d = M_PI / 180;
  c.T_parent_cam = make_pose(xyz, yaw * d, pitch * d, roll * d);
  c.T_parent_cam.linear() = c.T_parent_cam.linear() * R_view_optical();  // mount: x = optical axis
  return c;
}

// The example rig's panoramas: centred on the lenses, 1 m above base_link, on a sphere of
// 3 m radius; and the scene that coincides with that sphere.
ViewSpec example_panorama(int w, int h) {
  ViewSpec v = view(ViewType::kEquirectangular, w, h);
  v.position = Vec3(0, 0, 1);
  v.radius = 3.0;
  return v;
}
Scene sphere_around_example_rig() {
  Scene scene;
  scene.add(Sphere{Vec3(0, 0, 1), 3.0});
  return scene;
}

// Five greyscale 640x480 pinhole cameras placed like Spot's: two front cameras crossing
// (frontleft looks front-right), one per side, one at the back, tilted down and rolled as
// the physical sensors are.
Rig spot_like_rig() {
  Rig rig("body");
  const auto pinhole = [] { return CameraModel(PinholeRadtan(330, 330, 319.5, 239.5)); };
  rig.add_camera(camera("frontleft", pinhole(), 640, 480, Vec3(0.42, 0.04, 0.02), -35, 25, 78));
  rig.add_camera(camera("frontright", pinhole(), 640, 480, Vec3(0.42, -0.04, 0.02), 35, 25, 102 - 180));
  rig.add_camera(camera("left", pinhole(), 640, 480, Vec3(-0.05, 0.11, 0.03), 90, 30, 0));
  rig.add_camera(camera("right", pinhole(), 640, 480, Vec3(-0.05, -0.11, 0.03), -90, 30, 180));
  rig.add_camera(camera("back", pinhole(), 640, 480, Vec3(-0.43, 0, 0.03), 180, 30, 0));
  return rig;
}

void report(const std::string& what, const golden::Score& s) {
  std::cout << "[ golden ] " << what << ": PSNR " << s.psnr_db << " dB, coverage " << 100 * s.coverage << " %\n";
}

TEST(Golden, DualFisheyeEquirectangularOnSphere) {
  const Rig rig = golden::example_rig();
  const Scene scene = sphere_around_example_rig();
  ViewSpec v = example_panorama(720, 360);
  const auto s = golden::run(scene, rig, v, "base_link");
  report("dual fisheye, equirectangular", s);
  EXPECT_GT(s.psnr_db, kDualFisheyeBoundDb);
  EXPECT_GT(s.coverage, 0.999);
}

TEST(Golden, NaiveBackToBackStitchMisalignsTheRolledLens) {
  // The paper's Fig. 4: ignoring the back lens' 3 deg roll misplaces everything it sees.
  const Rig rig = golden::example_rig();
  Rig naive("base_link");
  for (Camera c : rig.cameras()) {
    if (c.name == "back") c.T_parent_cam.linear() = rotation_from_ypr(M_PI, 0, 0) * R_view_optical();
    naive.add_camera(c);
  }
  const Scene scene = sphere_around_example_rig();
  ViewSpec v = example_panorama(720, 360);
  const auto ours = golden::run(scene, rig, rig, v, "base_link");
  const auto stitched = golden::run(scene, rig, naive, v, "base_link");
  report("calibrated roll", ours);
  report("naive stitch", stitched);
  EXPECT_GT(ours.psnr_db, kDualFisheyeBoundDb);
  EXPECT_LT(stitched.psnr_db, ours.psnr_db - 20);  // measured 18.8 vs 53.4
}

TEST(Golden, SpotLikeRigBirdseyeOnFloor) {
  const Rig rig = spot_like_rig();
  Scene scene;
  scene.add(Plane{Vec3::UnitZ(), -0.5});  // the ground half a metre below the body frame
  ViewSpec v = view(ViewType::kBirdseye, 400, 400);
  v.pitch_deg = 90;
  v.height_m = 4;
  v.ground_z = -0.5;
  v.hfov_deg = 100;
  const auto s = golden::run(scene, rig, v, "body", /*grey_cameras=*/true, /*out_channels=*/1);
  report("spot-like bird's-eye", s);
  EXPECT_GT(s.psnr_db, 31);  // measured 35.5
  EXPECT_GT(s.coverage, 0.5);  // Spot's cameras leave gaps close to the body
}

TEST(Golden, SpotLikeRigFrontPerspectiveOnWall) {
  const Rig rig = spot_like_rig();
  ViewSpec v = view(ViewType::kPerspective, 512, 256);
  v.hfov_deg = 100;
  v.distance = 3.0;
  v.pitch_deg = 20;  // Spot's front cameras look down
  // A wall 3 m ahead along the view's axis: exactly the view's projection plane.
  Scene scene;
  scene.add(Plane{v.T_frame_view().linear() * Vec3::UnitX(), 3.0});
  const auto s = golden::run(scene, rig, v, "body", true, 1);
  report("spot-like front", s);
  EXPECT_GT(s.psnr_db, 49);  // measured 53.7
  EXPECT_GT(s.coverage, 0.9);
}

// A ring of four cameras, each with another model, around a panorama's surface.
Rig mixed_model_ring() {
  Rig rig;
  RadtanDistortion d;
  d.k1 = -0.28, d.k2 = 0.07, d.p1 = 0.0005, d.p2 = -0.0003;
  rig.add_camera(camera("omni", OmniRadtan(0.9, 240, 240, 319.5, 239.5, d), 640, 480, Vec3(0.1, 0, 1), 0, 0, 0, 190));
  rig.add_camera(camera("ds", DoubleSphere(-0.2, 0.6, 180, 180, 319.5, 239.5), 640, 480, Vec3(0, 0.1, 1), 90, 0, 5, 190));
  rig.add_camera(camera("eucm", Eucm(0.6, 1.1, 180, 180, 319.5, 239.5), 640, 480, Vec3(-0.1, 0, 1), 180, 0, -4, 180));
  rig.add_camera(camera("fov", Fov(250, 250, 319.5, 239.5, 0.9), 640, 480, Vec3(0, -0.1, 1), -90, 0, 0));
  RadtanDistortion r;
  r.k1 = -0.1, r.k2 = 0.01, r.p1 = 0.001, r.k3 = -0.001;
  rig.add_camera(camera("radtan", PinholeRadtan(200, 200, 319.5, 239.5, r), 640, 480, Vec3(0, 0, 1.1), 0, -89, 0));
  return rig;
}

TEST(Golden, CylindricalOnCylinderWithMixedModels) {
  const Rig rig = mixed_model_ring();
  Scene scene;
  scene.add(Cylinder{Vec3(0, 0, 0), 4.0, -10, 10});
  ViewSpec v = view(ViewType::kCylindrical, 720, 240);
  v.position = Vec3(0, 0, 1);
  v.radius = 4.0;
  v.vfov_deg = 90;
  const auto s = golden::run(scene, rig, v, "base_link");
  report("cylindrical, mixed models", s);
  EXPECT_GT(s.psnr_db, 38);  // measured 42.8
  EXPECT_GT(s.coverage, 0.99);
}

TEST(Golden, MercatorAndFisheyeOnSphere) {
  const Rig rig = mixed_model_ring();
  Scene scene;
  scene.add(Sphere{Vec3(0, 0, 1), 5.0});
  ViewSpec merc = view(ViewType::kMercator, 720, 360);
  merc.position = Vec3(0, 0, 1);
  merc.radius = 5.0;
  merc.lat_min_deg = -60, merc.lat_max_deg = 75;
  const auto m = golden::run(scene, rig, merc, "base_link");
  report("mercator", m);
  EXPECT_GT(m.psnr_db, 39);  // measured 43.9

  ViewSpec fish = view(ViewType::kFisheye, 400, 400);
  fish.position = Vec3(0, 0, 1);
  fish.radius = 5.0;
  fish.fov_deg = 250;
  fish.yaw_deg = 45;
  fish.pitch_deg = -20;
  const auto f = golden::run(scene, rig, fish, "base_link");
  report("fisheye view", f);
  EXPECT_GT(f.psnr_db, 38);  // measured 42.7
  EXPECT_GT(f.coverage, 0.95);  // the ring leaves small gaps between its lenses' fields
}

TEST(Golden, BlendedFusionMeetsTheSameBound) {
  const Rig rig = golden::example_rig();
  const Scene scene = sphere_around_example_rig();
  ViewSpec v = example_panorama(720, 360);
  v.fusion = Fusion::kBlend;
  v.feather_px = 30;
  const auto s = golden::run(scene, rig, v, "base_link");
  report("blend", s);
  EXPECT_GT(s.psnr_db, kDualFisheyeBoundDb);  // measured 53.4
  EXPECT_GT(s.coverage, 0.999);
}

TEST(Golden, MaskedHalfIsTakenFromTheOtherCamera) {
  const Rig example = golden::example_rig();  // named: a temporary's cameras() would dangle
  Rig masked("base_link");
  for (Camera c : example.cameras()) {
    if (c.name == "front") {  // blank the front lens' right half
      c.mask = cv::Mat(c.height, c.width, CV_8UC1, cv::Scalar(255));
      c.mask(cv::Rect(c.width / 2, 0, c.width / 2, c.height)).setTo(0);
    }
    masked.add_camera(c);
  }
  const ViewSpec v = example_panorama(360, 180);
  const auto map = build_map(masked, *View::create(v));
  // Straight ahead and 60 deg to the right (u = 3/4 of the width minus a bit): the front
  // lens' masked half; the back lens reaches 105 deg from its axis, i.e. to 75 deg from
  // the front, so 80 deg right must come from it.
  const int row = 90;
  const int right_80 = static_cast<int>((0.5 + 80.0 / 360) * 360);
  const int left_60 = static_cast<int>((0.5 - 60.0 / 360) * 360);
  EXPECT_EQ(map.primary[row * 360 + right_80].cam, 1) << "masked front pixel must come from the back lens";
  EXPECT_EQ(map.primary[row * 360 + left_60].cam, 0) << "unmasked front pixel stays with the front lens";
  const auto s = golden::run(sphere_around_example_rig(), masked, v, "base_link");
  report("half-masked front lens", s);
  EXPECT_GT(s.psnr_db, 41);  // measured 45.7
}

TEST(Golden, GreyAndMixedInputs) {
  const Rig rig = golden::example_rig();
  const Scene scene = sphere_around_example_rig();
  ViewSpec v = example_panorama(360, 180);
  const auto grey = golden::run(scene, rig, v, "base_link", true, 1);
  report("grey in, grey out", grey);
  EXPECT_GT(grey.psnr_db, kDualFisheyeBoundDb);  // measured 54.3
  const auto colour_to_grey = golden::run(scene, rig, v, "base_link", false, 1);
  report("colour in, grey out", colour_to_grey);
  EXPECT_GT(colour_to_grey.psnr_db, kDualFisheyeBoundDb);  // measured 53.6
}

}  // namespace
}  // namespace omniview

namespace omniview {
namespace {

TEST(Golden, OnePixelOfCalibrationErrorFailsTheBound) {
  // The harness must be sensitive: yaw the front lens' calibration by the angle of one
  // pixel (1/f rad) and the score has to fall below the bound.
  const Rig rig = golden::example_rig();
  Rig off_by_one("base_link");
  for (Camera c : rig.cameras()) {
    if (c.name == "front") c.T_parent_cam.linear() = rotation_from_ypr(1.0 / 258.0, 0, 0) * c.T_parent_cam.linear();
    off_by_one.add_camera(c);
  }
  const Scene scene = sphere_around_example_rig();
  ViewSpec v = example_panorama(720, 360);
  const auto s = golden::run(scene, rig, off_by_one, v, "base_link");
  report("front lens off by one pixel", s);
  EXPECT_LT(s.psnr_db, kDualFisheyeBoundDb);  // measured 40.3
}

}  // namespace
}  // namespace omniview
