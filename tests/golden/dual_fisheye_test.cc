// The bundled dual-fisheye rig (back lens rolled 3 deg) on a sphere around the lenses that
// coincides with an equirectangular panorama's surface: calibration, fusion policies,
// masks and grey/colour inputs. Thresholds: see the comment in thresholds.h.
#include <gtest/gtest.h>

#include <cmath>

#include "core/view/view.h"
#include "tests/golden/golden.h"
#include "tests/golden/thresholds.h"

namespace omniview {
namespace {

using golden::kWorld;

using synthetic::Scene;


TEST(GoldenDualFisheye, EquirectangularOnSphere) {
  const Rig rig = golden::example_rig();
  const ViewSpec v = golden::example_panorama(720, 360);
  const auto s = golden::run(golden::matching_scene(rig, v, kWorld), rig, v, kWorld);
  golden::report("dual fisheye, equirectangular", s);
  EXPECT_GT(s.psnr_db, kDualFisheyeBoundDb);
  EXPECT_GT(s.coverage, 0.999);
  for (const auto& c : s.cameras) EXPECT_GT(c.psnr_db, kDualFisheyeBoundDb) << c.name;
}

TEST(GoldenDualFisheye, NaiveBackToBackStitchMisalignsTheRolledLens) {
  // The paper's Fig. 4: a stitch that assumes the back lens is exactly opposite the front
  // one (roll 0) misplaces everything the back lens sees.
  const Rig rig = golden::example_rig();
  const Camera& back = *rig.find("back");
  Pose assumed = make_pose(back.T_parent_cam.translation(), M_PI, 0, 0);
  assumed.linear() = assumed.linear() * R_view_optical();
  const Rig naive = golden::with_camera_pose(rig, "back", assumed);
  const ViewSpec v = golden::example_panorama(720, 360);
  const Scene scene = golden::matching_scene(rig, v, kWorld);
  golden::Renders renders(scene, rig, kWorld);
  const auto ours = golden::run(renders, rig, v);
  const auto stitched = golden::run(renders, naive, v);
  golden::report("calibrated roll", ours);
  golden::report("naive stitch", stitched);
  EXPECT_GT(ours.psnr_db, kDualFisheyeBoundDb);
  EXPECT_LT(stitched.psnr_db, ours.psnr_db - kNaiveStitchMarginDb);
}

TEST(GoldenDualFisheye, OnePixelOfCalibrationErrorFailsTheBound) {
  // The harness must be sensitive: yaw the front lens' calibration by the angle of one
  // pixel at its centre (1/f rad) and the score has to fall below the bound.
  const Rig rig = golden::example_rig();
  const Camera& front = *rig.find("front");
  Pose off = front.T_parent_cam;
  off.linear() = rotation_from_ypr(1.0 / 258.0, 0, 0) * off.linear();
  const ViewSpec v = golden::example_panorama(720, 360);
  const auto s = golden::run(golden::matching_scene(rig, v, kWorld), rig, golden::with_camera_pose(rig, "front", off),
                             v, kWorld);
  golden::report("front lens off by one pixel", s);
  EXPECT_LT(s.psnr_db, kDualFisheyeBoundDb);
}

TEST(GoldenDualFisheye, BlendedFusionMeetsTheSameBound) {
  const Rig rig = golden::example_rig();
  ViewSpec v = golden::example_panorama(720, 360);
  v.fusion = Fusion::kBlend;
  v.feather_px = 30;
  const auto s = golden::run(golden::matching_scene(rig, v, kWorld), rig, v, kWorld);
  golden::report("blend", s);
  EXPECT_GT(s.psnr_db, kDualFisheyeBoundDb);
  EXPECT_GT(s.coverage, 0.999);
}

TEST(GoldenDualFisheye, MaskedHalfIsTakenFromTheOtherCamera) {
  const Rig example = golden::example_rig();  // named: a temporary's cameras() would dangle
  Rig masked(example.default_frame());
  for (Camera c : example.cameras()) {
    if (c.name == "front") {  // blank the front lens' right half
      c.mask = cv::Mat(c.height, c.width, CV_8UC1, cv::Scalar(255));
      c.mask(cv::Rect(c.width / 2, 0, c.width / 2, c.height)).setTo(0);
    }
    masked.add_camera(c);
  }
  const ViewSpec v = golden::example_panorama(360, 180);
  const auto map = build_map(masked, *View::create(v));
  // On the horizon, 80 deg to the right lies in the front lens' masked half but within
  // the back lens' reach (105 deg from its axis: up to 75 deg right of forward); 60 deg
  // to the left is the front lens' own.
  const int row = 90;
  const int right_80 = static_cast<int>((0.5 + 80.0 / 360) * 360);
  const int left_60 = static_cast<int>((0.5 - 60.0 / 360) * 360);
  EXPECT_EQ(map.primary[row * 360 + right_80].cam, 1) << "masked front pixel must come from the back lens";
  EXPECT_EQ(map.primary[row * 360 + left_60].cam, 0) << "unmasked front pixel stays with the front lens";
  const auto s = golden::run(golden::matching_scene(masked, v, kWorld), masked, v, kWorld);
  golden::report("half-masked front lens", s);
  EXPECT_GT(s.psnr_db, kMaskedBoundDb);
  // Right of forward, between the lenses' reaches, nobody sees: coverage drops by that band.
  EXPECT_LT(s.coverage, 0.95);
  EXPECT_GT(s.coverage, 0.8);
}

TEST(GoldenDualFisheye, GreyAndMixedInputs) {
  using golden::Inputs;
  const Rig rig = golden::example_rig();
  const ViewSpec v = golden::example_panorama(360, 180);
  const Scene scene = golden::matching_scene(rig, v, kWorld);
  golden::Renders renders(scene, rig, kWorld);  // one render per lens for all five cases
  struct Case {
    const char* what;
    Inputs inputs;
    int out_channels;
  };
  for (const Case& c : {Case{"grey in, grey out", Inputs::kGrey, 1}, Case{"grey in, colour out", Inputs::kGrey, 3},
                        Case{"colour in, grey out", Inputs::kColour, 1},
                        Case{"grey front + colour back, colour out", Inputs::kMixed, 3},
                        Case{"grey front + colour back, grey out", Inputs::kMixed, 1}}) {
    const auto s = golden::run(renders, rig, v, c.inputs, c.out_channels);
    golden::report(c.what, s);
    EXPECT_EQ(s.rendered.channels(), c.out_channels) << c.what;
    EXPECT_GT(s.psnr_db, kDualFisheyeBoundDb) << c.what;
    EXPECT_GT(s.coverage, 0.999) << c.what;
    for (const auto& cam : s.cameras) EXPECT_GT(cam.psnr_db, kDualFisheyeBoundDb) << c.what << ": " << cam.name;
  }
}

}  // namespace
}  // namespace omniview
