// The adaptive map builder must agree with the exact one: same camera almost everywhere
// and coordinates within the interpolation tolerance, for every view type, on rigs with
// seams, fisheye circles and masks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

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
    const bool exact_two = exact.secondary[i].cam != kNoCamera, adaptive_two = adaptive.secondary[i].cam != kNoCamera;
    if (!exact_two && !adaptive_two) {
      EXPECT_EQ(adaptive.primary_weight[i], 256) << spec.name << " pixel " << i;
      continue;
    }
    ++two;
    const bool same = exact.secondary[i].cam == adaptive.secondary[i].cam &&
                      exact.secondary[i].offset == adaptive.secondary[i].offset &&
                      exact.primary[i].cam == adaptive.primary[i].cam &&
                      exact.primary[i].offset == adaptive.primary[i].offset &&
                      exact.primary_weight[i] == adaptive.primary_weight[i];
    if (same) continue;
    ++differ;
    worst_missed = std::max(worst_missed, 256 - int(exact.primary_weight[i]));
  }
  // An overlap to test: all views here but the dual fisheye's forward perspective have one.
  if (spec.type != ViewType::kPerspective) {
    EXPECT_GT(two, exact.primary.size() / 50) << spec.name;
  }
  // Measured: 5 of 27,500 overlap pixels differ in the masked equirectangular view, 45 of
  // 27,462 in five pinholes' bird's-eye view (where two image corners meet between samples:
  // a 50/50 blend shown as one of its cameras), none elsewhere.
  EXPECT_LE(double(differ), 0.003 * double(two))
      << spec.name << ": " << differ << " of " << two << " overlap pixels differ, a second camera lost up to "
      << worst_missed << "/256";
  EXPECT_EQ(adaptive.camera_used, exact.camera_used) << spec.name;
  EXPECT_EQ(exact.gain_samples.empty(), adaptive.gain_samples.empty()) << spec.name;
  const double gain_ratio = exact.gain_samples.empty() ? 1 : double(adaptive.gain_samples.size()) / double(exact.gain_samples.size());
  EXPECT_NEAR(gain_ratio, 1.0, 0.01) << spec.name << ": gain samples";
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

// The feather weights made beforehand (a measured-depth view's, once per revision) give
// the same map as made by build_map; ones that do not fit (another feather width, another
// rig) are not used.
TEST(AdaptiveMap, BlendWithFeathersMadeBeforehandIsTheSame) {
  const Rig rig = five_pinholes();
  ViewSpec s = spec(ViewType::kEquirectangular, 400, 200);
  s.fusion = Fusion::kBlend;
  const auto view = View::create(s);
  const FeatherSet fitting = feather_set(rig, s.feather_px);
  const FeatherSet other_width = feather_set(rig, s.feather_px * 2);
  const FeatherSet other_rig = feather_set(dual_fisheye(false), s.feather_px);
  EXPECT_TRUE(fitting.fits(rig, s.feather_px));
  EXPECT_FALSE(other_width.fits(rig, s.feather_px));
  EXPECT_FALSE(other_rig.fits(rig, s.feather_px));
  for (const MapPrecision precision : {MapPrecision::kExact, MapPrecision::kAdaptive}) {
    const FusionMap made_here = build_map(rig, *view, precision, Sampling::kBilinear);
    for (const FeatherSet* feathers : {&fitting, &other_width, &other_rig}) {
      const FusionMap given = build_map(rig, *view, precision, Sampling::kBilinear, nullptr, feathers);
      ASSERT_EQ(given.primary.size(), made_here.primary.size());
      size_t differ = 0;
      for (size_t i = 0; i < given.primary.size(); ++i) {
        differ += std::memcmp(&given.primary[i], &made_here.primary[i], sizeof(MapEntry)) != 0 ||
                  std::memcmp(&given.secondary[i], &made_here.secondary[i], sizeof(MapEntry)) != 0 ||
                  given.primary_weight[i] != made_here.primary_weight[i];
      }
      EXPECT_EQ(differ, 0u);
    }
  }
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
