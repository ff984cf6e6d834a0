// Camera models: project/unproject round trips over each model's whole field of view (in
// both directions) and the edges of what each model can image.
#include "core/camera/camera_model.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>

#include "camera_cases.h"
#include "test_support.h"

namespace omniview {
namespace {

using testing::camera_cases;
using testing::CameraCase;
using testing::kDeg;
using testing::ray_at;

class EveryModel : public ::testing::TestWithParam<CameraCase> {};

// ray -> pixel -> ray on a dense grid of angles up to just inside the model's limit: past
// 90 deg for the fisheye, omni, ds and eucm cases. Within ~0.5 deg of a fold the inverse is
// ill-conditioned (d pixel / d angle -> 0), so the sweep stops there; the edge itself is
// probed by the validity tests below.
TEST_P(EveryModel, RayPixelRayRoundTripOverTheWholeField) {
  const CameraCase& c = GetParam();
  const double last = c.max_theta - 0.5 * kDeg;
  int checked = 0;
  for (int i = 0;; ++i) {
    const double theta = std::min(i * 0.5 * kDeg, last);
    for (double phi_deg = 1.3; phi_deg < 360; phi_deg += 7.5) {
      const Eigen::Vector3d ray = ray_at(theta, phi_deg * kDeg);
      Eigen::Vector2d uv;
      // Any distance along the ray images at the same pixel.
      ASSERT_TRUE(project(c.model, 3.7 * ray, uv)) << "theta " << theta / kDeg << " phi " << phi_deg;
      Eigen::Vector3d back;
      ASSERT_TRUE(unproject(c.model, uv, back))
          << "theta " << theta / kDeg << " phi " << phi_deg << " uv " << uv.transpose();
      EXPECT_NEAR(back.norm(), 1, 1e-12) << "unproject returns unit rays";
      // Angle between the rays (asin of the chord is accurate for tiny angles).
      EXPECT_LT(2 * std::asin(std::min(1.0, 0.5 * (back - ray).norm())), 1e-9)
          << "theta " << theta / kDeg << " phi " << phi_deg;
      ++checked;
    }
    if (theta == last) break;
  }
  EXPECT_GT(checked, 48 * 80) << "the sweep must cover a real field";
}

// pixel -> ray -> pixel on a grid reaching well beyond the image: wherever unproject finds
// a ray, projecting it must give the same pixel back.
TEST_P(EveryModel, PixelRayPixelRoundTrip) {
  const CameraCase& c = GetParam();
  int inside = 0, unprojected = 0;
  const double step_u = c.width / 64.0, step_v = c.height / 48.0;
  for (double u = -c.width; u <= 2 * c.width; u += step_u) {
    for (double v = -c.height; v <= 2 * c.height; v += step_v) {
      const bool in_image = u >= 0 && v >= 0 && u <= c.width - 1 && v <= c.height - 1;
      inside += in_image;
      Eigen::Vector3d ray;
      if (!unproject(c.model, {u, v}, ray)) continue;
      ++unprojected;
      Eigen::Vector2d uv;
      ASSERT_TRUE(project(c.model, ray, uv)) << "pixel " << u << ", " << v << " ray " << ray.transpose();
      EXPECT_LT((uv - Eigen::Vector2d(u, v)).norm(), 1e-6) << "pixel " << u << ", " << v;
    }
  }
  // Every one of these calibrations covers at least a third of its image.
  EXPECT_GT(unprojected, inside / 3);
}

// The model's limit as derived in camera_cases.h from the published validity condition
// must be exactly where project() stops accepting points.
TEST_P(EveryModel, ValidityEdgeIsTheModelsLimit) {
  const CameraCase& c = GetParam();
  for (double phi_deg = 0; phi_deg < 360; phi_deg += 22.5) {
    Eigen::Vector2d uv;
    const double phi = phi_deg * kDeg;
    EXPECT_TRUE(project(c.model, 2.0 * ray_at(c.max_theta - 1e-6, phi), uv)) << "just inside, phi " << phi_deg;
    if (c.max_theta < M_PI - 1e-6) {
      EXPECT_FALSE(project(c.model, 2.0 * ray_at(c.max_theta + 1e-6, phi), uv)) << "just outside, phi " << phi_deg;
    }
  }
  Eigen::Vector2d uv;
  EXPECT_FALSE(project(c.model, {0, 0, -2}, uv)) << "straight behind is never imageable";
  EXPECT_FALSE(project(c.model, {0, 0, 0}, uv)) << "the centre of projection is not a point to image";
}

INSTANTIATE_TEST_SUITE_P(CameraModel, EveryModel, ::testing::ValuesIn(camera_cases()), [](const auto& info) {
  std::string name = info.param.name;
  for (char& ch : name) {
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  }
  return name;
});

TEST(CameraModel, PinholeAndFovImageOnlyPointsInFront) {
  for (const CameraModel& m :
       {CameraModel(PinholeRadtan(400, 400, 320, 240)), CameraModel(Fov(380, 381, 320, 240, 0.9))}) {
    Eigen::Vector2d uv;
    EXPECT_TRUE(project(m, {0.1, 0.1, 1e-6}, uv));
    EXPECT_FALSE(project(m, {0.1, 0.1, 0.0}, uv));
    EXPECT_FALSE(project(m, {1.0, 0.0, -1e-6}, uv));
    EXPECT_FALSE(project(m, {0.0, 0.0, -1.0}, uv));
    EXPECT_FALSE(project(m, {0.0, 0.0, 0.0}, uv));
  }
}

TEST(CameraModel, FovUnprojectStopsAtNinetyDegrees) {
  // r_d = atan(2 r tan(w/2)) / w approaches pi / (2 w) as r -> infinity.
  const Fov m(380, 381, 320, 240, 0.92);
  const double rim = M_PI / (2 * 0.92);
  Eigen::Vector3d ray;
  EXPECT_TRUE(m.unproject(320 + 380 * rim * 0.999, 240, ray));
  EXPECT_GT(ray.z(), 0);
  EXPECT_FALSE(m.unproject(320 + 380 * rim * 1.001, 240, ray));
}

TEST(CameraModel, RadtanRejectsPointsBeyondTheFoldOver) {
  // Strong barrel distortion: r (1 - 0.3 r^2) turns at r = 1 / sqrt(0.9); past it the
  // polynomial folds back and would put far-off points at the wrong place in the image.
  RadtanDistortion d;
  d.k1 = -0.3;
  const PinholeRadtan m(400, 400, 320, 240, d);
  const double r_fold = 1 / std::sqrt(0.9);
  EXPECT_NEAR(d.max_radius(), r_fold, 1e-9);
  double u, v;
  for (double phi = 0; phi < 2 * M_PI; phi += 0.5) {
    const double x = std::cos(phi), y = std::sin(phi);
    EXPECT_TRUE(m.project(r_fold * (1 - 1e-6) * x, r_fold * (1 - 1e-6) * y, 1.0, u, v));
    EXPECT_FALSE(m.project(r_fold * (1 + 1e-6) * x, r_fold * (1 + 1e-6) * y, 1.0, u, v));
    EXPECT_FALSE(m.project(3 * x, 3 * y, 1.0, u, v)) << "folded back inside the image, still rejected";
  }
  // The fold's image is a circle of radius f * g(r_fold); pixels beyond it have no ray.
  const double rim = 400 * r_fold * (1 - 0.3 * r_fold * r_fold);
  Eigen::Vector3d ray;
  EXPECT_TRUE(m.unproject(320 + rim * 0.999, 240, ray));
  EXPECT_FALSE(m.unproject(320 + rim * 1.01, 240, ray));
  EXPECT_FALSE(m.unproject(320, 240 - rim * 1.01, ray));
}

TEST(CameraModel, RadtanWithoutFoldUnprojectsFarOut) {
  // EuRoC's k2 > 0 never folds, so points 85 deg off-axis are imageable (millions of pixels
  // out); unproject must still invert them, not give up after a fixed number of steps.
  const PinholeRadtan m(458.654, 457.296, 367.215, 248.375,
                        testing::radtan(-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05));
  for (double theta_deg : {60.0, 75.0, 84.0, 88.0}) {
    const Eigen::Vector3d ray = ray_at(theta_deg * kDeg, 0.7);
    Eigen::Vector2d uv;
    ASSERT_TRUE(project(m, ray, uv));
    Eigen::Vector3d back;
    ASSERT_TRUE(unproject(m, uv, back)) << theta_deg << " deg at " << uv.transpose();
    EXPECT_LT((back - ray).norm(), 1e-9) << theta_deg;
  }
}

TEST(CameraModel, KannalaBrandt210RoundTripsBeyondNinetyDegrees) {
  // theta = atan2(r, z), not atan(r / z): at 100 deg (z < 0) the pixel must lie on the far
  // side of the 90 deg circle, in the direction of (x, y), and come back to the same ray.
  const Equidistant m(258, 258, 511.5, 511.5, 0.02, -0.004, 0.0005, -0.0001);
  const auto d = [](double t) {
    return t * (1 + 0.02 * t * t - 0.004 * std::pow(t, 4) + 0.0005 * std::pow(t, 6) - 0.0001 * std::pow(t, 8));
  };
  for (double theta_deg : {90.0, 95.0, 100.0, 105.0}) {
    for (double phi : {0.0, 1.0, 2.5, 4.0}) {
      const Eigen::Vector3d ray = ray_at(theta_deg * kDeg, phi);
      double u, v;
      ASSERT_TRUE(m.project(ray.x(), ray.y(), ray.z(), u, v)) << theta_deg;
      EXPECT_NEAR(std::hypot(u - 511.5, v - 511.5), 258 * d(theta_deg * kDeg), 1e-9) << theta_deg;
      EXPECT_NEAR(std::atan2(v - 511.5, u - 511.5), std::remainder(phi, 2 * M_PI), 1e-12);
      Eigen::Vector3d back;
      ASSERT_TRUE(m.unproject(u, v, back));
      EXPECT_LT((back - ray).norm(), 1e-9) << theta_deg;
    }
  }
}

TEST(CameraModel, KannalaBrandtLimitIsWhereThePolynomialTurns) {
  // d(theta) = theta (1 - 0.1 theta^2) turns at theta = sqrt(1 / 0.3).
  const Equidistant m(300, 300, 320, 240, -0.1, 0, 0, 0);
  const double limit = std::sqrt(1 / 0.3);
  EXPECT_NEAR(m.max_theta(), limit, 1e-9);
  double u, v;
  const Eigen::Vector3d inside = ray_at(limit - 1e-6, 0.3), outside = ray_at(limit + 1e-6, 0.3);
  EXPECT_TRUE(m.project(inside.x(), inside.y(), inside.z(), u, v));
  EXPECT_FALSE(m.project(outside.x(), outside.y(), outside.z(), u, v));
  // Pixels beyond the image of the limit, f d(limit), have no ray.
  const double rim = 300 * limit * (1 - 0.1 * limit * limit);
  Eigen::Vector3d ray;
  EXPECT_TRUE(m.unproject(320 + rim * 0.999, 240, ray));
  EXPECT_FALSE(m.unproject(320 + rim * 1.001, 240, ray));
}

TEST(CameraModel, KannalaBrandtSeesAlmostAllAroundButNotStraightBehind) {
  // Ideal equidistant r = f theta never turns: valid up to (not including) theta = pi. A
  // point on the axis behind the lens has no direction in the image; it used to be
  // reported valid at the principal point.
  const Equidistant m(100, 100, 320, 240, 0, 0, 0, 0);
  double u, v;
  const Eigen::Vector3d near_behind = ray_at(179.9 * kDeg, 1.0);
  ASSERT_TRUE(m.project(near_behind.x(), near_behind.y(), near_behind.z(), u, v));
  EXPECT_NEAR(std::hypot(u - 320, v - 240), 100 * 179.9 * kDeg, 1e-9);
  EXPECT_FALSE(m.project(0.0, 0.0, -1.0, u, v));
  EXPECT_FALSE(m.project(1e-14, 0.0, -1.0, u, v));
  float uf, vf;
  EXPECT_FALSE(m.project(0.0f, 0.0f, -1.0f, uf, vf)) << "the float path agrees";
  EXPECT_TRUE(m.project(0.0, 0.0, 1.0, u, v)) << "the axis in front is fine";
  EXPECT_EQ(u, 320);
  EXPECT_EQ(v, 240);
}

TEST(CameraModel, MeiHorizonDependsOnXi) {
  // xi < 1: z > -xi |p|. xi > 1: the projection centre lies outside the unit sphere and
  // points past the tangent from it (z_s < -1/xi) would fold over onto visible ones.
  for (double xi : {0.0, 0.4, 0.9, 1.5, 2.5}) {
    const OmniRadtan m(xi, 300, 300, 320, 240);
    const double edge = std::acos(-(xi <= 1 ? xi : 1 / xi));
    double u, v;
    for (double phi : {0.0, 1.0, 3.0}) {
      const Eigen::Vector3d in = ray_at(edge - 1e-6, phi), out = ray_at(edge + 1e-6, phi);
      EXPECT_TRUE(m.project(in.x(), in.y(), in.z(), u, v)) << "xi " << xi;
      EXPECT_FALSE(m.project(out.x(), out.y(), out.z(), u, v)) << "xi " << xi;
    }
  }
  // xi = 1 (a parabolic mirror's model) sees everything but the point straight behind.
  const OmniRadtan parabolic(1.0, 300, 300, 320, 240);
  double u, v;
  const Eigen::Vector3d almost_behind = ray_at(179.9 * kDeg, 0.5);
  EXPECT_TRUE(parabolic.project(almost_behind.x(), almost_behind.y(), almost_behind.z(), u, v));
  EXPECT_FALSE(parabolic.project(0.0, 0.0, -1.0, u, v));
}

TEST(CameraModel, DoubleSphereAndEucmRejectPixelsOutsideTheirImageDisc) {
  // For alpha > 0.5 both models image everything inside a disc of radius
  // 1 / sqrt(2 alpha - 1) (DS) or 1 / sqrt(beta (2 alpha - 1)) (EUCM) in normalised units;
  // beyond it there is no ray at all.
  const DoubleSphere ds(-0.2, 0.6, 350, 351, 320, 240);
  const Eucm eucm(0.6, 1.1, 350, 351, 320, 240);
  const double ds_disc = 1 / std::sqrt(0.2), eucm_disc = 1 / std::sqrt(1.1 * 0.2);
  Eigen::Vector3d ray;
  EXPECT_FALSE(ds.unproject(320 + 350 * ds_disc * 1.001, 240, ray));
  EXPECT_FALSE(eucm.unproject(320, 240 + 351 * eucm_disc * 1.001, ray));
  // EUCM's validity bound is exactly its disc; DS's published bound (w2) is conservative and
  // stops just short of it: pixels in that sliver unproject past z = -w2 |p| and are refused.
  Eigen::Vector2d uv;
  ASSERT_TRUE(project(CameraModel(ds), ray_at(testing::ds_max_theta(-0.2, 0.6) - 1e-9, 0), uv));
  const double ds_rim = (uv.x() - 320) / 350;
  ASSERT_LT(ds_rim, ds_disc);
  EXPECT_TRUE(ds.unproject(320 + 350 * ds_rim * 0.999, 240, ray));
  EXPECT_FALSE(ds.unproject(320 + 350 * 0.5 * (ds_rim + ds_disc), 240, ray));
  ASSERT_TRUE(project(CameraModel(eucm), ray_at(testing::eucm_max_theta(0.6, 1.1) - 1e-9, M_PI_2), uv));
  EXPECT_NEAR((uv.y() - 240) / 351, eucm_disc, 1e-6);
  EXPECT_TRUE(eucm.unproject(320, 240 + 351 * eucm_disc * 0.999, ray));
}

TEST(CameraModel, PrincipalPointIsTheOpticalAxis) {
  for (const auto& c : camera_cases()) {
    const ModelSpec s = describe(c.model);
    // Principal point: the last two intrinsics in every kalibr model.
    const Eigen::Vector2d pp(s.intrinsics[s.intrinsics.size() - 2], s.intrinsics.back());
    Eigen::Vector2d uv;
    ASSERT_TRUE(project(c.model, {0, 0, 2.5}, uv)) << c.name;
    EXPECT_LT((uv - pp).norm(), 1e-12) << c.name;
    Eigen::Vector3d ray;
    ASSERT_TRUE(unproject(c.model, pp, ray)) << c.name;
    EXPECT_LT((ray - Eigen::Vector3d::UnitZ()).norm(), 1e-12) << c.name;
  }
}

}  // namespace
}  // namespace omniview
