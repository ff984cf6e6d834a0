// The adaptive map builder must agree with the exact one: same camera almost everywhere
// and coordinates within the interpolation tolerance, for every view type, on rigs with
// seams, fisheye circles and masks.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/core.hpp>

#include "core/map/apply.h"
#include "core/map/fusion_map.h"
#include "core/rig/rig.h"
#include "core/view/view.h"

namespace omniview {
namespace {

Camera fisheye(const std::string& name, double yaw_deg, double roll_deg, double x) {
  Camera c;
  c.name = name;
  c.width = c.height = 400;
  c.model = Equidistant(120, 121, 199.5, 200.5, 0.02, -0.01, 0.002, -0.0003);
  c.fov_deg = 210;
  c.T_parent_cam = make_pose(Vec3(x, 0, 1), yaw_deg * M_PI / 180, 0, roll_deg * M_PI / 180);
  c.T_parent_cam.linear() = c.T_parent_cam.linear() * R_view_optical();
  return c;
}

Rig dual_fisheye(bool with_mask) {
  Rig rig;
  Camera front = fisheye("front", 0, 0, 0.02);
  if (with_mask) {  // a strut across the front image
    front.mask = cv::Mat(400, 400, CV_8UC1, cv::Scalar(255));
    front.mask(cv::Rect(180, 0, 30, 400)).setTo(0);
  }
  rig.add_camera(front);
  rig.add_camera(fisheye("back", 180, 3, -0.02));
  return rig;
}

Rig five_pinholes() {
  Rig rig;
  const double yaws[] = {20, -20, 90, -90, 180};
  for (int i = 0; i < 5; ++i) {
    Camera c;
    c.name = "cam" + std::to_string(i);
    c.width = 320, c.height = 240;
    RadtanDistortion d;
    d.k1 = -0.2, d.k2 = 0.05, d.p1 = 0.001;
    c.model = PinholeRadtan(160, 160, 159.5, 119.5, d);
    c.T_parent_cam = make_pose(Vec3(0.3 * std::cos(yaws[i] * M_PI / 180), 0.3 * std::sin(yaws[i] * M_PI / 180), 0.5),
                               yaws[i] * M_PI / 180, 30 * M_PI / 180, 0);
    c.T_parent_cam.linear() = c.T_parent_cam.linear() * R_view_optical();
    rig.add_camera(c);
  }
  return rig;
}

Vec2 decode(const MapEntry& e, int camera_width) {
  return Vec2(e.offset % camera_width + e.fx / 256.0, e.offset / camera_width + e.fy / 256.0);
}

void expect_agreement(const Rig& rig, const ViewSpec& spec) {
  const auto view = View::create(spec);
  const FusionMap exact = build_map(rig, *view, MapPrecision::kExact, Sampling::kBilinear);
  const FusionMap adaptive = build_map(rig, *view, MapPrecision::kAdaptive, Sampling::kBilinear);
  size_t same_camera = 0, worst_index = 0;
  double worst = 0;
  for (size_t i = 0; i < exact.primary.size(); ++i) {
    const MapEntry& a = exact.primary[i];
    const MapEntry& b = adaptive.primary[i];
    if (a.cam != b.cam) {
      // Only where both cameras see the point: never black where exact has a picture.
      EXPECT_NE(b.cam, kNoCamera) << spec.name << " pixel " << i;
      EXPECT_NE(a.cam, kNoCamera) << spec.name << " pixel " << i;
      continue;
    }
    ++same_camera;
    if (a.cam == kNoCamera) continue;
    const int w = rig.cameras()[a.cam].width;
    const double d = (decode(a, w) - decode(b, w)).cwiseAbs().maxCoeff();
    if (d > worst) worst = d, worst_index = i;
  }
  EXPECT_LE(worst, 0.06) << spec.name << ": worst coordinate error at pixel " << worst_index;
  EXPECT_GE(static_cast<double>(same_camera) / exact.primary.size(), 0.995) << spec.name;
  EXPECT_NEAR(exact.coverage(), adaptive.coverage(), 1e-3) << spec.name;
}

// Blend maps: interpolated only where one camera sees a block, so the primary agrees as
// for nearest-centre, and the second camera and the weights are the per-pixel builder's
// wherever two cameras see the pixel, but for slivers where a camera's region pokes
// between the samples of a block.
void expect_blend_agreement(const Rig& rig, ViewSpec spec) {
  spec.fusion = Fusion::kBlend;
  expect_agreement(rig, spec);
  const auto view = View::create(spec);
  const FusionMap exact = build_map(rig, *view, MapPrecision::kExact, Sampling::kBilinear);
  const FusionMap adaptive = build_map(rig, *view, MapPrecision::kAdaptive, Sampling::kBilinear);
  ASSERT_EQ(adaptive.secondary.size(), exact.secondary.size());
  ASSERT_EQ(adaptive.primary_weight.size(), exact.primary_weight.size());
  size_t two = 0, differ = 0;
  int worst_missed = 0;
  for (size_t i = 0; i < exact.primary.size(); ++i) {
    two += exact.secondary[i].cam != kNoCamera;
    const bool same = exact.secondary[i].cam == adaptive.secondary[i].cam &&
                      exact.primary_weight[i] == adaptive.primary_weight[i] &&
                      (exact.secondary[i].cam == kNoCamera ||
                       (exact.secondary[i].offset == adaptive.secondary[i].offset &&
                        exact.primary[i].offset == adaptive.primary[i].offset));
    if (same) continue;
    ++differ;
    worst_missed = std::max(worst_missed, 256 - int(exact.primary_weight[i]));
  }
  // Measured: at most 45 of 90,000 pixels differ (five pinholes' bird's-eye view, where two
  // image corners meet between samples), each a 50/50 blend shown as one of its cameras.
  if (spec.type != ViewType::kPerspective) EXPECT_GT(two, exact.primary.size() / 50) << spec.name;  // an overlap to test
  EXPECT_LE(double(differ), 0.001 * double(exact.primary.size()))
      << spec.name << ": " << differ << " pixels differ, a second camera lost up to " << worst_missed << "/256";
  EXPECT_EQ(exact.gain_samples.empty(), adaptive.gain_samples.empty()) << spec.name;
}

ViewSpec spec(ViewType type, int w, int h) {
  ViewSpec s;
  s.name = to_string(type);
  s.type = type;
  s.width = w, s.height = h;
  s.hfov_deg = 120;
  s.fov_deg = 360;
  if (type == ViewType::kMercator) s.lat_min_deg = -80, s.lat_max_deg = 80;
  s.pitch_deg = type == ViewType::kBirdseye ? 90 : 0;
  s.height_m = 2;
  return s;
}

TEST(AdaptiveMap, AgreesWithExactOnDualFisheye) {
  const Rig rig = dual_fisheye(false);
  for (ViewType t : {ViewType::kPerspective, ViewType::kBirdseye, ViewType::kCylindrical, ViewType::kMercator,
                     ViewType::kEquirectangular, ViewType::kFisheye}) {
    expect_agreement(rig, spec(t, 333, 171));  // sizes not multiples of the block
  }
}

TEST(AdaptiveMap, AgreesWithExactWithMasks) {
  expect_agreement(dual_fisheye(true), spec(ViewType::kEquirectangular, 512, 256));
}

TEST(AdaptiveMap, AgreesWithExactOnFivePinholesWithGaps) {
  const Rig rig = five_pinholes();
  expect_agreement(rig, spec(ViewType::kEquirectangular, 400, 200));
  expect_agreement(rig, spec(ViewType::kBirdseye, 300, 300));
}

TEST(AdaptiveMap, BlendAgreesWithExact) {
  const Rig fisheyes = dual_fisheye(false);
  for (ViewType t : {ViewType::kPerspective, ViewType::kBirdseye, ViewType::kEquirectangular, ViewType::kFisheye}) {
    expect_blend_agreement(fisheyes, spec(t, 333, 171));
  }
  expect_blend_agreement(dual_fisheye(true), spec(ViewType::kEquirectangular, 512, 256));
  const Rig pinholes = five_pinholes();
  expect_blend_agreement(pinholes, spec(ViewType::kEquirectangular, 400, 200));
  expect_blend_agreement(pinholes, spec(ViewType::kBirdseye, 300, 300));
}

TEST(AdaptiveMap, TinyViews) {
  const Rig rig = dual_fisheye(false);
  for (auto [w, h] : {std::pair{1, 1}, std::pair{2, 2}, std::pair{9, 1}, std::pair{1, 17}, std::pair{10, 9}}) {
    expect_agreement(rig, spec(ViewType::kPerspective, w, h));
  }
}

// A robot that has not answered yet has a rig without cameras: its views are black, and
// building their maps must not read a camera that is not there.
TEST(AdaptiveMap, RigWithoutCamerasGivesABlackView) {
  Rig rig("body");
  rig.add_frame("footprint", "body", Pose::Identity());
  for (const Fusion fusion : {Fusion::kNearestCentre, Fusion::kBlend}) {
    ViewSpec s = spec(ViewType::kPerspective, 64, 32);
    s.frame = "body";
    s.fusion = fusion;
    const FusionMap map = build_map(rig, *View::create(s));
    EXPECT_TRUE(map.camera_used.empty());
    ASSERT_EQ(map.primary.size(), 64u * 32u);
    for (const auto& e : map.primary) EXPECT_EQ(e.cam, kNoCamera);
    cv::Mat out;
    apply_map(map, {}, out, 1);
    EXPECT_EQ(cv::countNonZero(out), 0);
  }
}

}  // namespace
}  // namespace omniview
