// The remaining view types over a ring of cameras with one model each (omni+radtan, double
// sphere, EUCM, FOV, pinhole+radtan): every model must place its share of the surface
// right. Thresholds: see thresholds.h.
#include <gtest/gtest.h>

#include "tests/golden/golden.h"
#include "tests/golden/thresholds.h"

namespace omniview {
namespace {

using golden::kWorld;


void expect_every_camera_contributes(const golden::Score& s, double bound_db) {
  for (const auto& c : s.cameras) {
    EXPECT_GT(c.pixels, 500u) << c.name << " should be the primary source somewhere";
    EXPECT_GT(c.psnr_db, bound_db) << c.name;
  }
}

TEST(GoldenModels, CylindricalOnCylinder) {
  const Rig rig = golden::mixed_model_ring();
  ViewSpec v = golden::view(ViewType::kCylindrical, 720, 360);
  v.position = Vec3(0, 0, 1);
  v.radius = 4.0;
  v.vfov_deg = 90;
  const auto s = golden::run(golden::matching_scene(rig, v, kWorld), rig, v, kWorld);
  golden::report("cylindrical, mixed models", s);
  EXPECT_GT(s.psnr_db, kCylindricalBoundDb);
  EXPECT_GT(s.coverage, 0.99);
  expect_every_camera_contributes(s, kPerCameraModelBoundDb);
}

TEST(GoldenModels, MercatorOnSphere) {
  const Rig rig = golden::mixed_model_ring();
  ViewSpec v = golden::view(ViewType::kMercator, 720, 360);
  v.position = Vec3(0, 0, 1);
  v.radius = 5.0;
  v.lat_min_deg = -60, v.lat_max_deg = 75;
  const auto s = golden::run(golden::matching_scene(rig, v, kWorld), rig, v, kWorld);
  golden::report("mercator, mixed models", s);
  EXPECT_GT(s.psnr_db, kMercatorBoundDb);
  EXPECT_GT(s.coverage, 0.99);
  expect_every_camera_contributes(s, kPerCameraModelBoundDb);
}

TEST(GoldenModels, FisheyeOnSphere) {
  const Rig rig = golden::mixed_model_ring();
  ViewSpec v = golden::view(ViewType::kFisheye, 400, 400);
  v.position = Vec3(0, 0, 1);
  v.radius = 5.0;
  v.fov_deg = 250;
  v.yaw_deg = 45;
  v.pitch_deg = -20;
  const auto s = golden::run(golden::matching_scene(rig, v, kWorld), rig, v, kWorld);
  golden::report("fisheye view, mixed models", s);
  EXPECT_GT(s.psnr_db, kFisheyeBoundDb);
  EXPECT_GT(s.coverage, 0.95);  // the ring leaves small gaps between its lenses' fields
  expect_every_camera_contributes(s, kPerCameraModelBoundDb);
}

TEST(GoldenModels, PerspectiveThroughEachModel) {
  // One wall straight ahead of each camera: that camera alone renders the view.
  const Rig rig = golden::mixed_model_ring();
  for (const Camera& cam : rig.cameras()) {
    ViewSpec v = golden::view(ViewType::kPerspective, 320, 240);
    v.name = cam.name;
    v.position = cam.T_parent_cam.translation();
    const Vec3 ypr = ypr_from_rotation(cam.T_parent_cam.linear() * R_view_optical().transpose());
    v.yaw_deg = ypr[0] * 180 / M_PI, v.pitch_deg = ypr[1] * 180 / M_PI, v.roll_deg = ypr[2] * 180 / M_PI;
    v.hfov_deg = 70;
    v.distance = 2.5;
    const auto s = golden::run(golden::matching_scene(rig, v, kWorld), rig, v, kWorld);
    golden::report("perspective through " + cam.name, s);
    EXPECT_GT(s.psnr_db, kPerspectivePerModelBoundDb) << cam.name;
    EXPECT_GT(s.coverage, 0.999) << cam.name;
  }
}

}  // namespace
}  // namespace omniview
