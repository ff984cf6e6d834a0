// A Spot-like rig of five rotated greyscale pinholes: the floor under a bird's-eye view and
// a wall under the front perspective view. Thresholds: see thresholds.h.
#include <gtest/gtest.h>

#include "tests/golden/golden.h"
#include "tests/golden/thresholds.h"

namespace omniview {
namespace {

using golden::Inputs;

TEST(GoldenSpotLike, BirdseyeOnFloor) {
  const Rig rig = golden::spot_like_rig();
  ViewSpec v = golden::view(ViewType::kBirdseye, 400, 400);
  v.pitch_deg = 90;
  v.height_m = 4;
  v.ground_z = -0.5;  // the ground half a metre below the body frame
  v.hfov_deg = 100;
  const auto s = golden::run(golden::matching_scene(rig, v, "body"), rig, v, "body", Inputs::kGrey, 1);
  golden::report("spot-like bird's-eye", s);
  EXPECT_GT(s.psnr_db, kSpotFloorBoundDb);
  EXPECT_GT(s.coverage, 0.85);  // Spot's cameras leave gaps close to the body
  for (const auto& c : s.cameras) EXPECT_GT(c.pixels, 1000u) << c.name << " must see some of the floor";
}

TEST(GoldenSpotLike, FrontPerspectiveOnWall) {
  const Rig rig = golden::spot_like_rig();
  ViewSpec v = golden::view(ViewType::kPerspective, 512, 256);
  v.hfov_deg = 100;
  v.distance = 3.0;
  v.pitch_deg = 20;  // Spot's front cameras look down
  const auto s = golden::run(golden::matching_scene(rig, v, "body"), rig, v, "body", Inputs::kGrey, 1);
  golden::report("spot-like front", s);
  EXPECT_GT(s.psnr_db, kSpotWallBoundDb);
  EXPECT_GT(s.coverage, 0.99);
  EXPECT_GT(s.cameras[0].pixels, 10000u) << "frontleft";
  EXPECT_GT(s.cameras[1].pixels, 10000u) << "frontright";
}

}  // namespace
}  // namespace omniview
