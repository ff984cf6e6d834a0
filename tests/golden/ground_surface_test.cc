// `ground: true` (core/view/view.h): Spot's front view fuses two crossing cameras whose
// overlap runs down the middle of the picture. On a plane 3 m ahead, the floor a metre in
// front of the robot is doubled and cut by a hard seam there (the cameras are 10 cm apart
// and see it from different sides); with the surface cut at the ground, both cameras map
// every floor point to the same pixel, so the floor is whole and sharp across the seam.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include <opencv2/imgproc.hpp>

#include "core/view/view.h"
#include "tests/golden/golden.h"

namespace omniview {
namespace {

constexpr double kFloorZ = -0.52;  // Spot's standing body height: the floor in `body`

// config/spot.yaml's front view, posed in body (the golden rig has no footprint frame).
ViewSpec spot_front(bool ground) {
  ViewSpec v = default_view_spec(ViewType::kPerspective);
  v.name = "front";
  v.width = 1024, v.height = 512;
  v.frame = "body";
  v.position = Vec3(0.42, 0, 0);
  v.pitch_deg = 27;
  v.hfov_deg = 115;
  v.distance = 3;
  v.fusion = Fusion::kBlend;
  v.feather_px = 30;
  v.ground = ground;
  v.ground_z = kFloorZ;
  return v;
}

// PSNR of the rendered view against the floor as a camera at the view's centre would see
// it, over covered pixels whose ray meets the floor within 6 m, in columns [lo, hi).
double floor_psnr(const golden::Score& s, const ViewSpec& spec, int lo, int hi, size_t* compared) {
  const auto view = View::create(spec);
  const Pose T = spec.T_frame_view();
  double error = 0;
  size_t n = 0;
  for (int v = 0; v < spec.height; ++v) {
    for (int u = lo; u < hi; ++u) {
      const uint8_t got = s.rendered.at<uint8_t>(v, u);
      Vec3 dir;
      if (got == 0 || !view->pixel_to_direction(u, v, dir)) continue;
      const Vec3 d = T.linear() * dir;
      if (d.z() > -1e-6) continue;
      const Vec3 p = T.translation() + d * ((kFloorZ - T.translation().z()) / d.z());
      if ((p - T.translation()).norm() > 6) continue;
      const Vec3 bgr = synthetic::Scene::texture(p);
      const double luma = 0.114 * bgr.x() + 0.587 * bgr.y() + 0.299 * bgr.z();
      error += (got - luma) * (got - luma);
      ++n;
    }
  }
  *compared = n;
  return n == 0 ? 0 : 10 * std::log10(255.0 * 255.0 / (error / n));
}

TEST(GroundSurface, SpotFrontShowsTheFloorWholeAcrossTheSeam) {
  const Rig rig = golden::spot_like_rig();
  const synthetic::Scene floor = synthetic::Scene::floor(kFloorZ);
  golden::Renders renders(floor, rig, "body");  // both views map the same images
  double whole[2], seam[2];
  for (const bool ground : {false, true}) {
    const ViewSpec spec = spot_front(ground);
    const auto score = golden::run(renders, rig, spec, golden::Inputs::kGrey, 1);
    size_t n_whole = 0, n_seam = 0;
    whole[ground] = floor_psnr(score, spec, 0, spec.width, &n_whole);
    // The front cameras' overlap is centred; the blend band lies within 60 px of the middle.
    seam[ground] = floor_psnr(score, spec, spec.width / 2 - 60, spec.width / 2 + 60, &n_seam);
    std::cout << "[ ground ] spot front, ground " << ground << ": floor " << whole[ground] << " dB over " << n_whole
              << " px, centre band " << seam[ground] << " dB over " << n_seam << " px\n";
    ASSERT_GT(n_seam, 20000u) << "the floor fills the centre band's lower part";
  }
  // Measured: the floor 21.9 dB on the plane, 38.8 dB on the ground; the centre band 28.7
  // and 36.1 dB (the far floor there is at the cameras' resolution limit).
  EXPECT_GT(whole[true], 35);
  EXPECT_GT(whole[true], whole[false] + 10);
  EXPECT_GT(seam[true], seam[false] + 5);
}

TEST(GroundSurface, ARayAboveTheHorizonKeepsTheTypesSurface) {
  ViewSpec spec = spot_front(true);
  const auto view = View::create(spec);
  Vec3 up, down;
  ASSERT_TRUE(view->pixel_to_point(spec.width / 2.0, 0, up));       // 11 deg above the horizon
  ASSERT_TRUE(view->pixel_to_point(spec.width / 2.0, spec.height - 1, down));
  EXPECT_NEAR(up.x(), spec.distance, 1e-9) << "the plane 3 m ahead";
  const Vec3 down_in_body = spec.T_frame_view() * down;
  EXPECT_NEAR(down_in_body.z(), kFloorZ, 1e-9) << "the floor";
  // The map builder's float rows agree with pixel_to_point.
  std::vector<float> x(spec.width), y(spec.width), z(spec.width);
  std::vector<uint8_t> valid(spec.width);
  view->row_points(spec.height - 1, x.data(), y.data(), z.data(), valid.data());
  EXPECT_NEAR(x[spec.width / 2], down.x(), 1e-4);
  EXPECT_NEAR(z[spec.width / 2], down.z(), 1e-4);
}

TEST(GroundSurface, ABadGroundIsRefusedWithItsField) {
  ViewSpec below = spot_front(true);
  below.ground_z = 0.5;  // above the view's origin
  EXPECT_THROW(
      {
        try {
          validate(below);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("ground"), std::string::npos) << e.what();
          throw;
        }
      },
      std::invalid_argument);
  ViewSpec birdseye = default_view_spec(ViewType::kBirdseye);
  birdseye.ground = true;
  EXPECT_THROW(validate(birdseye), std::invalid_argument);
}

}  // namespace
}  // namespace omniview
