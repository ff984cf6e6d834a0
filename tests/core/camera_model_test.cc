// Camera models: round trips over each model's whole field of view, validity edges,
// published closed-form values, the float path the map builder uses, and errors.
#include <gtest/gtest.h>

#include <cmath>

#include "core/camera/camera_model.h"
#include "core/camera/fast_math.h"

namespace omniview {
namespace {

constexpr double kDeg = M_PI / 180;

struct NamedModel {
  std::string name;
  CameraModel model;
  double max_angle_deg;  // test rays up to this angle from the optical axis
};

std::vector<NamedModel> models() {
  RadtanDistortion radtan;
  radtan.k1 = -0.28, radtan.k2 = 0.07, radtan.p1 = 0.0007, radtan.p2 = -0.0004, radtan.k3 = -0.005;
  return {
      {"pinhole", PinholeRadtan(460, 458, 320.5, 241.2), 70},
      {"pinhole-radtan", PinholeRadtan(460, 458, 320.5, 241.2, radtan), 45},
      {"equidistant-210", Equidistant(258, 259, 511.5, 512.5, 0.02, -0.004, 0.0005, -0.0001), 105},
      {"fov", Fov(380, 381, 320, 240, 0.92), 75},
      {"omni", OmniRadtan(0.9, 700, 701, 320, 240), 100},
      {"omni-radtan", OmniRadtan(0.9, 700, 701, 320, 240, radtan), 60},
      {"ds", DoubleSphere(-0.2, 0.6, 350, 351, 320, 240), 95},
      {"eucm", Eucm(0.6, 1.1, 350, 351, 320, 240), 95},
  };
}

Eigen::Vector3d ray_at(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

TEST(CameraModel, RayPixelRayRoundTripOverTheWholeField) {
  for (const auto& m : models()) {
    for (double theta_deg = 0; theta_deg <= m.max_angle_deg; theta_deg += 2.5) {
      for (double phi_deg = 0; phi_deg < 360; phi_deg += 15) {
        const Eigen::Vector3d ray = ray_at(theta_deg * kDeg, phi_deg * kDeg);
        Eigen::Vector2d uv;
        ASSERT_TRUE(project(m.model, ray * 2.7, uv)) << m.name << " theta " << theta_deg << " phi " << phi_deg;
        Eigen::Vector3d back;
        ASSERT_TRUE(unproject(m.model, uv, back)) << m.name << " theta " << theta_deg;
        EXPECT_NEAR((back.normalized() - ray).norm(), 0, 1e-9) << m.name << " theta " << theta_deg << " phi " << phi_deg;
      }
    }
  }
}

TEST(CameraModel, PixelRayPixelRoundTrip) {
  for (const auto& m : models()) {
    for (double u = 0; u <= 640; u += 20) {
      for (double v = 0; v <= 480; v += 20) {
        Eigen::Vector3d ray;
        if (!unproject(m.model, {u, v}, ray)) continue;
        Eigen::Vector2d uv;
        ASSERT_TRUE(project(m.model, ray, uv)) << m.name << " at " << u << "," << v;
        EXPECT_NEAR((uv - Eigen::Vector2d(u, v)).norm(), 0, 1e-6) << m.name << " at " << u << "," << v;
      }
    }
  }
}

TEST(CameraModel, PinholeImagesOnlyPointsInFront) {
  const CameraModel m = PinholeRadtan(400, 400, 320, 240);
  Eigen::Vector2d uv;
  EXPECT_TRUE(project(m, {0.1, 0.1, 1e-3}, uv));
  EXPECT_FALSE(project(m, {0.1, 0.1, 0.0}, uv));
  EXPECT_FALSE(project(m, {0.0, 0.0, -1.0}, uv));
}

TEST(CameraModel, RadtanRejectsPointsBeyondTheFoldOver) {
  // Strong barrel distortion folds back at r ~ 1.1; imaging beyond it would put far-off
  // points at the wrong place in the image.
  RadtanDistortion d;
  d.k1 = -0.3;
  const PinholeRadtan m(400, 400, 320, 240, d);
  const double r_fold = d.max_radius();
  EXPECT_NEAR(r_fold, 1 / std::sqrt(0.9), 1e-6);  // slope 1 - 3 * 0.3 r^2 = 0
  double u, v;
  EXPECT_TRUE(m.project(r_fold * 0.99, 0.0, 1.0, u, v));
  EXPECT_FALSE(m.project(r_fold * 1.01, 0.0, 1.0, u, v));
}

TEST(CameraModel, KannalaBrandtSeesBeyond180Degrees) {
  const Equidistant m(258, 258, 511.5, 511.5, 0, 0, 0, 0);  // ideal equidistant: r = f theta
  for (double theta_deg : {90.0, 100.0, 105.0, 179.0}) {
    double u, v;
    const auto ray = ray_at(theta_deg * kDeg, 0);
    ASSERT_TRUE(m.project(ray.x(), ray.y(), ray.z(), u, v)) << theta_deg;
    EXPECT_NEAR(u - 511.5, 258 * theta_deg * kDeg, 1e-9) << "r = f theta, theta = atan2(r, z)";
  }
}

TEST(CameraModel, KannalaBrandtLimitIsWhereThePolynomialTurns) {
  // d(theta) = theta (1 - 0.1 theta^2) turns at theta = sqrt(1/0.3).
  const Equidistant m(300, 300, 320, 240, -0.1, 0, 0, 0);
  EXPECT_NEAR(m.max_theta(), std::sqrt(1 / 0.3), 1e-3);
  double u, v;
  const auto inside = ray_at(m.max_theta() - 0.01, 0.3), outside = ray_at(m.max_theta() + 0.01, 0.3);
  EXPECT_TRUE(m.project(inside.x(), inside.y(), inside.z(), u, v));
  EXPECT_FALSE(m.project(outside.x(), outside.y(), outside.z(), u, v));
}

TEST(CameraModel, UnifiedModelsRejectPointsBehindTheirHorizon) {
  // Mei with xi = 0.9: imageable while z > -xi |p|; DS and EUCM: paper's validity bounds.
  const OmniRadtan omni(0.9, 300, 300, 320, 240);
  double u, v;
  const double a = std::acos(-0.9);  // angle from the axis where z = -0.9 |p|
  EXPECT_TRUE(omni.project(std::sin(a - 0.02), 0.0, std::cos(a - 0.02), u, v));
  EXPECT_FALSE(omni.project(std::sin(a + 0.02), 0.0, std::cos(a + 0.02), u, v));

  const Eucm eucm(0.6, 1.0, 300, 300, 320, 240);  // beta = 1: unified model with xi = 1.5
  const double b = std::acos(-1 / 1.5);
  EXPECT_TRUE(eucm.project(std::sin(b - 0.02), 0.0, std::cos(b - 0.02), u, v));
  EXPECT_FALSE(eucm.project(std::sin(b + 0.02), 0.0, std::cos(b + 0.02), u, v));

  const DoubleSphere ds(0.0, 0.5, 300, 300, 320, 240);  // xi = 0, alpha = 0.5: w2 = 1/1
  EXPECT_FALSE(ds.project(0.0, 0.0, -1.0, u, v));
  EXPECT_TRUE(ds.project(1.0, 0.0, -0.9, u, v));
}

TEST(CameraModel, ClosedFormReferenceValues) {
  double u, v;
  // Double sphere (Usenko et al. eq. 40-42) for p = (1, 0, 1), xi = 0.5, alpha = 0.5:
  // d1 = sqrt2, zz = 0.5 sqrt2 + 1, d2 = sqrt(1 + zz^2), u = f / (0.5 d2 + 0.5 zz) + cx.
  const double zz = 0.5 * std::sqrt(2.0) + 1, d2 = std::sqrt(1 + zz * zz);
  DoubleSphere(0.5, 0.5, 100, 100, 0, 0).project(1.0, 0.0, 1.0, u, v);
  EXPECT_NEAR(u, 100 / (0.5 * d2 + 0.5 * zz), 1e-12);
  // EUCM (Khomutenko et al. eq. 4): rho = sqrt(beta (x^2 + y^2) + z^2), u = f x / (a rho + (1 - a) z).
  Eucm(0.5, 2.0, 100, 100, 0, 0).project(1.0, 0.0, 1.0, u, v);
  EXPECT_NEAR(u, 100 / (0.5 * std::sqrt(3.0) + 0.5), 1e-12);
  // Mei: m = x / (z + xi |p|).
  OmniRadtan(1.0, 100, 100, 0, 0).project(1.0, 0.0, 1.0, u, v);
  EXPECT_NEAR(u, 100 / (1 + std::sqrt(2.0)), 1e-12);
  // FOV (Devernay-Faugeras): r_d = atan(2 r tan(w/2)) / w.
  Fov(100, 100, 0, 0, 1.0).project(1.0, 0.0, 1.0, u, v);
  EXPECT_NEAR(u, 100 * std::atan(2 * std::tan(0.5)) / 1.0, 1e-12);
}

TEST(CameraModel, FastAtanIsAccurate) {
  double worst = 0;
  for (double a = 0; a <= M_PI; a += 1e-4) {
    const float y = static_cast<float>(std::sin(a)), x = static_cast<float>(std::cos(a));
    worst = std::max(worst, std::abs(double(fast::atan2_nonneg_y(y, x)) - std::atan2(double(y), double(x))));
  }
  EXPECT_LT(worst, 1e-6);
  float c, s;
  for (double t = 0; t <= M_PI; t += 1e-3) {
    fast::cos_and_sinc(static_cast<float>(t * t), c, s);
    EXPECT_NEAR(c, std::cos(t), 2e-6);
    EXPECT_NEAR(s, t > 0 ? std::sin(t) / t : 1.0, 2e-6);
  }
}

TEST(CameraModel, FloatProjectionAgreesWithDouble) {
  for (const auto& m : models()) {
    for (double theta_deg = 0; theta_deg <= m.max_angle_deg; theta_deg += 5) {
      for (double phi_deg = 0; phi_deg < 360; phi_deg += 30) {
        const Eigen::Vector3d ray = ray_at(theta_deg * kDeg, phi_deg * kDeg) * 3.0;  // not auto: Eigen temporaries
        double ud, vd;
        float uf, vf;
        std::visit([&](const auto& model) {
          ASSERT_TRUE(model.project(ray.x(), ray.y(), ray.z(), ud, vd));
          ASSERT_TRUE(model.project(float(ray.x()), float(ray.y()), float(ray.z()), uf, vf));
        }, m.model);
        EXPECT_NEAR(uf, ud, 2e-3) << m.name << " theta " << theta_deg;
        EXPECT_NEAR(vf, vd, 2e-3) << m.name << " theta " << theta_deg;
      }
    }
  }
}

TEST(CameraModel, DescribeRoundTripsThroughTheFactory) {
  for (const auto& m : models()) {
    const ModelSpec spec = describe(m.model);
    const CameraModel again = make_camera_model(spec, m.name);
    const ModelSpec spec2 = describe(again);
    EXPECT_EQ(spec.camera_model, spec2.camera_model) << m.name;
    EXPECT_EQ(spec.distortion_model, spec2.distortion_model) << m.name;
    EXPECT_EQ(spec.intrinsics, spec2.intrinsics) << m.name;
    EXPECT_EQ(spec.distortion, spec2.distortion) << m.name;
  }
}

void expect_error(const ModelSpec& spec, const std::string& needle) {
  try {
    make_camera_model(spec, "rig.yaml: camera 'cam7'");
    ADD_FAILURE() << "accepted " << spec.camera_model << "+" << spec.distortion_model;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rig.yaml: camera 'cam7'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(CameraModel, BadSpecsAreClearErrors) {
  expect_error({"kb4", "none", {1, 1, 0, 0}, {}}, "unknown camera_model 'kb4'");
  expect_error({"ds", "radtan", {0, 0.5, 1, 1, 0, 0}, {0, 0, 0, 0}}, "distortion_model none");
  expect_error({"pinhole", "radtan", {1, 1, 0}, {0, 0, 0, 0}}, "intrinsics needs 4 values");
  expect_error({"pinhole", "radtan", {1, 1, 0, 0}, {0, 0, 0}}, "distortion_coeffs needs 4 or 5 values");
  expect_error({"pinhole", "equidistant", {1, 1, 0, 0}, {0, 0, 0, 0, 0}}, "distortion_coeffs needs 4 values");
  expect_error({"omni", "none", {0.9, 1, 1, 0}, {}}, "intrinsics needs 5 values");
  expect_error({"pinhole", "none", {-1, 1, 0, 0}, {}}, "focal lengths");
  expect_error({"pinhole", "none", {NAN, 1, 0, 0}, {}}, "non-finite");
  expect_error({"eucm", "none", {1.5, 1, 1, 1, 0, 0}, {}}, "alpha must be in [0, 1]");
  expect_error({"pinhole", "kb", {1, 1, 0, 0}, {}}, "distortion_model 'kb' is not supported");
}

}  // namespace
}  // namespace omniview
