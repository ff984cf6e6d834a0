// The float projection path the map builder runs (with the polynomial atan of
// fast_math.h) against the double path and libm.
#include <gtest/gtest.h>

#include <cmath>
#include <variant>

#include "camera_cases.h"
#include "core/camera/camera_model.h"
#include "core/camera/fast_math.h"
#include "test_support.h"

namespace omniview {
namespace {

using testing::kDeg;
using testing::ray_at;

TEST(FastMath, Atan2IsWithinAMicroradianOverZeroToPi) {
  // As the models call it: y is a radius >= 0, x = z of either sign, magnitudes from
  // millimetres to kilometres.
  double worst = 0;
  for (double scale : {1e-3, 1.0, 37.0, 1e4}) {
    for (int i = 0; i <= 200000; ++i) {
      const double a = M_PI * i / 200000;
      const float y = static_cast<float>(scale * std::sin(a)), x = static_cast<float>(scale * std::cos(a));
      // Reference on the float inputs actually passed, so only the approximation counts.
      const double err = std::abs(double(fast::atan2_nonneg_y(y, x)) - std::atan2(double(y), double(x)));
      worst = std::max(worst, err);
    }
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_EQ(fast::atan2_nonneg_y(0.0f, 1.0f), 0.0f);
  EXPECT_NEAR(fast::atan2_nonneg_y(1.0f, 0.0f), M_PI_2, 1e-7);
  EXPECT_NEAR(fast::atan2_nonneg_y(0.0f, -1.0f), M_PI, 1e-6);
  EXPECT_EQ(fast::atan2_nonneg_y(0.0f, 0.0f), 0.0f) << "the origin: any finite angle, not NaN";
}

TEST(FastMath, PolynomialMeetsItsDocumentedBound) {
  double worst = 0;
  for (int i = 0; i <= 1000000; ++i) {
    const double x = i / 1e6;
    worst = std::max(worst, std::abs(fast::atan_unit(x) - std::atan(x)));
  }
  EXPECT_LT(worst, 4e-8);
  // The double instantiations the models use are libm itself.
  EXPECT_EQ(fast::atan2_radius(0.3, -0.7), std::atan2(0.3, -0.7));
  EXPECT_EQ(fast::atan_nonneg(2.5), std::atan(2.5));
}

TEST(FastMath, CosAndSincOverZeroToPi) {
  for (int i = 0; i <= 3142; ++i) {
    const double t = std::min(i * 1e-3, M_PI);
    float c, s;
    fast::cos_and_sinc(static_cast<float>(t * t), c, s);
    EXPECT_NEAR(c, std::cos(t), 2e-6) << t;
    EXPECT_NEAR(s, t > 0 ? std::sin(t) / t : 1.0, 2e-6) << t;
  }
}

struct FloatCase {
  std::string name;
  CameraModel model;
  double half_fov_deg;  // sweep the lens' field, not the model's mathematical one
  int width, height;
};
void PrintTo(const FloatCase& c, std::ostream* os) { *os << c.name; }

std::vector<FloatCase> typical_calibrations() {
  using testing::radtan;
  return {
      // 640 x 480
      {"pinhole_radtan_640",
       PinholeRadtan(458.654, 457.296, 319.5, 239.5, radtan(-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05)), 45,
       640, 480},
      {"pinhole_radtan5_640", PinholeRadtan(500, 500, 320, 240, radtan(-0.3, 0.12, 0.001, -0.0005, -0.02)), 50, 640,
       480},
      {"equidistant_190_640", Equidistant(185, 185.5, 319.5, 239.5, -0.012, 0.0021, -0.0007, 0.0001), 95, 640, 480},
      {"fov_640", Fov(280, 281, 319.5, 239.5, 0.93), 75, 640, 480},
      {"omni_radtan_640", OmniRadtan(1.1, 520, 521, 319.5, 239.5, radtan(-0.12, 0.03, 0.0004, -0.0002)), 100, 640, 480},
      {"ds_640", DoubleSphere(-0.18, 0.59, 200, 200.5, 319.5, 239.5), 95, 640, 480},
      {"eucm_640", Eucm(0.62, 1.05, 190, 190.5, 319.5, 239.5), 95, 640, 480},
      // 1024 x 1024 fisheyes: the Insta360 Air-like 210 deg lens of the examples, a DS.
      {"equidistant_210_1024", Equidistant(258, 258, 511.5, 511.5, 0.02, -0.004, 0.0005, -0.0001), 105, 1024, 1024},
      {"ds_1024", DoubleSphere(-0.2, 0.6, 300, 300, 511.5, 511.5), 100, 1024, 1024},
      {"eucm_1024", Eucm(0.6, 1.1, 300, 300, 511.5, 511.5), 100, 1024, 1024},
  };
}

class TypicalCalibration : public ::testing::TestWithParam<FloatCase> {};

TEST_P(TypicalCalibration, FloatProjectionAgreesWithDoubleOverTheLensField) {
  const FloatCase& c = GetParam();
  double worst = 0;
  int compared = 0;
  for (double theta_deg = 0; theta_deg <= c.half_fov_deg; theta_deg += 0.5) {
    for (double phi_deg = 0.7; phi_deg < 360; phi_deg += 5) {
      const Eigen::Vector3d p = 2.3 * ray_at(theta_deg * kDeg, phi_deg * kDeg);
      std::visit(
          [&](const auto& m) {
            double ud, vd;
            float uf, vf;
            const bool ok_d = m.project(p.x(), p.y(), p.z(), ud, vd);
            const bool ok_f = m.project(float(p.x()), float(p.y()), float(p.z()), uf, vf);
            ASSERT_TRUE(ok_d) << "theta " << theta_deg;
            ASSERT_EQ(ok_f, ok_d) << "theta " << theta_deg << " phi " << phi_deg;
            worst = std::max(worst, std::hypot(double(uf) - ud, double(vf) - vd));
            ++compared;
          },
          c.model);
    }
  }
  EXPECT_LT(worst, 1e-3) << "px";
  EXPECT_GT(compared, 1000);
}

// The same seen from the image: every pixel's ray, projected in float, lands within
// 1e-3 px of the pixel.
TEST_P(TypicalCalibration, FloatProjectionHitsThePixelsOfTheImage) {
  const FloatCase& c = GetParam();
  double worst = 0;
  int hits = 0;
  for (int v = 0; v < c.height; v += 7) {
    for (int u = 0; u < c.width; u += 7) {
      Eigen::Vector3d ray;
      if (!unproject(c.model, Eigen::Vector2d(u, v), ray)) continue;
      if (ray.z() < std::cos(c.half_fov_deg * kDeg)) continue;  // outside the lens
      std::visit(
          [&](const auto& m) {
            float uf, vf;
            ASSERT_TRUE(m.project(float(ray.x()), float(ray.y()), float(ray.z()), uf, vf)) << u << ", " << v;
            worst = std::max(worst, std::hypot(double(uf) - u, double(vf) - v));
            ++hits;
          },
          c.model);
    }
  }
  EXPECT_LT(worst, 1e-3) << "px";
  EXPECT_GT(hits, (c.width / 7) * (c.height / 7) / 3);
}

INSTANTIATE_TEST_SUITE_P(CameraFloat, TypicalCalibration, ::testing::ValuesIn(typical_calibrations()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace omniview
