// Reference values: pixels worked out by hand (a few lines of Python following each
// paper's equations, digits pasted here) and identities between models that the papers
// state. Independent of the code under test, unlike a round trip.
#include <gtest/gtest.h>

#include <cmath>

#include "core/camera/camera_model.h"
#include "test_support.h"

namespace omniview {
namespace {

using testing::kDeg;
using testing::ray_at;

template <typename M>
Eigen::Vector2d px(const M& m, double x, double y, double z) {
  Eigen::Vector2d uv;
  EXPECT_TRUE(m.project(x, y, z, uv.x(), uv.y())) << x << " " << y << " " << z;
  return uv;
}

TEST(CameraReference, DoubleSphereUsenkoEq40To42) {
  // xi = -0.2, alpha = 0.6, f = (350, 351), c = (320, 240). d1 = |p|, zz = xi d1 + z,
  // d2 = |(x, y, zz)|, u = fx x / (alpha d2 + (1 - alpha) zz) + cx.
  const DoubleSphere m(-0.2, 0.6, 350, 351, 320, 240);
  EXPECT_LT((px(m, 0.4, -0.3, 0.5) - Eigen::Vector2d(593.115348523199, 34.578241432194)).norm(), 1e-9);
  // Behind the image plane but inside the valid cone (about 107 deg of 122 deg).
  EXPECT_LT((px(m, 1.0, 0.5, -0.3) - Eigen::Vector2d(980.177010064896, 571.031615046827)).norm(), 1e-9);
  // Closed-form unprojection (eq. 47-50) of pixel (700, 100).
  Eigen::Vector3d ray;
  ASSERT_TRUE(m.unproject(700, 100, ray));
  EXPECT_LT((ray - Eigen::Vector3d(0.754779541394080, -0.277284431911155, 0.594492378178771)).norm(), 1e-12);
}

TEST(CameraReference, EucmKhomutenko) {
  // alpha = 0.6, beta = 1.1: rho = sqrt(beta (x^2 + y^2) + z^2),
  // u = fx x / (alpha rho + (1 - alpha) z) + cx.
  const Eucm m(0.6, 1.1, 350, 351, 320, 240);
  EXPECT_LT((px(m, 0.4, -0.3, 0.5) - Eigen::Vector2d(540.562297543595, 74.105643347568)).norm(), 1e-9);
  EXPECT_LT((px(m, 1.0, 0.5, -0.3) - Eigen::Vector2d(897.345199171763, 529.497378441841)).norm(), 1e-9);
  Eigen::Vector3d ray;
  ASSERT_TRUE(m.unproject(700, 100, ray));
  EXPECT_LT((ray - Eigen::Vector3d(0.856089673477069, -0.314502878995175, 0.410119994720656)).norm(), 1e-12);
}

TEST(CameraReference, MeiWithRadtan) {
  // m = (x, y) / (z + xi |p|), then plumb_bob with k1 k2 p1 p2 k3.
  RadtanDistortion d;
  d.k1 = -0.28, d.k2 = 0.07, d.p1 = 0.0007, d.p2 = -0.0004, d.k3 = -0.005;
  EXPECT_LT(
      (px(OmniRadtan(0.9, 700, 701, 320, 240, d), 0.4, -0.3, 0.5) - Eigen::Vector2d(553.460043809008, 64.709113720207))
          .norm(),
      1e-9);
  // xi = 1.5, a point behind the image plane.
  EXPECT_LT(
      (px(OmniRadtan(1.5, 700, 701, 320, 240), 1.0, 0.5, -0.3) - Eigen::Vector2d(807.337734971957, 484.016965868101))
          .norm(),
      1e-9);
}

TEST(CameraReference, PinholeRadtan) {
  RadtanDistortion euroc;
  euroc.k1 = -0.28340811, euroc.k2 = 0.07395907, euroc.p1 = 0.00019359, euroc.p2 = 1.76187114e-05;
  EXPECT_LT((px(PinholeRadtan(458.654, 457.296, 367.215, 248.375, euroc), 0.4, -0.3, 1.0) -
             Eigen::Vector2d(538.509310563915, 120.308290715527))
                .norm(),
            1e-9);
  // Five coefficients: r^2 = 0.25, radial = 1 - 0.075 + 0.0075 - 0.0003125 = 0.9321875;
  // u = 500 (0.4 radial + 2 p1 x y + p2 (r^2 + 2 x^2)) + 320 = 506.175 exactly.
  RadtanDistortion k5;
  k5.k1 = -0.3, k5.k2 = 0.12, k5.p1 = 0.001, k5.p2 = -0.0005, k5.k3 = -0.02;
  EXPECT_LT((px(PinholeRadtan(500, 500, 320, 240, k5), 0.4, -0.3, 1.0) - Eigen::Vector2d(506.175, 100.446875)).norm(),
            1e-9);
}

TEST(CameraReference, KannalaBrandtAtAndBeyondNinetyDegrees) {
  // d(theta) = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8); a point in
  // the image plane's own plane (theta = pi/2) lands at radius f d(pi/2).
  const Equidistant m(258, 259, 511.5, 512.5, 0.02, -0.004, 0.0005, -0.0001);
  const double d90 = 1.616035488604925, d100 = 1.796518811414183;
  EXPECT_LT((px(m, 1.0, 0.0, 0.0) - Eigen::Vector2d(511.5 + 258 * d90, 512.5)).norm(), 1e-9);
  EXPECT_LT((px(m, 0.0, -2.0, 0.0) - Eigen::Vector2d(511.5, 512.5 - 259 * d90)).norm(), 1e-9);
  const Eigen::Vector3d at100 = ray_at(100 * kDeg, 0);
  EXPECT_LT((px(m, at100.x(), at100.y(), at100.z()) - Eigen::Vector2d(511.5 + 258 * d100, 512.5)).norm(), 1e-9);
  EXPECT_LT((px(m, 0.4, -0.3, -0.2) - Eigen::Vector2d(924.214171758837, 201.764620681574)).norm(), 1e-9);
}

TEST(CameraReference, FovDevernayFaugeras) {
  // r_d = atan(2 r tan(w / 2)) / w on r = |(x, y)| / z.
  EXPECT_LT(
      (px(Fov(380, 381, 320, 240, 0.92), 0.4, -0.3, 0.5) - Eigen::Vector2d(578.012121102299, 45.981674723732)).norm(),
      1e-9);
  // r = tan(w/2) maps to r_d = atan(2 tan^2(w/2)) / w, and the model's rim (r -> infinity)
  // is r_d = pi / (2 w).
  const Fov m(100, 100, 0, 0, 1.0);
  EXPECT_NEAR(px(m, std::tan(0.5), 0, 1).x(), 100 * std::atan(2 * std::tan(0.5) * std::tan(0.5)), 1e-9);
  EXPECT_NEAR(px(m, 1e6, 0, 1).x(), 100 * M_PI / 2, 1e-3);
}

// Identities stated in the papers: the unified model is DS with alpha = 0 and EUCM with
// beta = 1 (alpha = xi / (1 + xi), f_eucm = f / (1 + xi)); DS with xi = 0 is EUCM with
// beta = 1; Mei with xi = 0 is a pinhole; KB with k = 0 is the ideal r = f theta.
TEST(CameraReference, ModelsCoincideWhereThePapersSayTheyDo) {
  const double xi = 0.8, f = 400;
  const OmniRadtan mei(xi, f, f, 320, 240);
  const DoubleSphere ds_as_mei(xi, 0.0, f, f, 320, 240);
  const Eucm eucm_as_mei(xi / (1 + xi), 1.0, f / (1 + xi), f / (1 + xi), 320, 240);
  const DoubleSphere ds_xi0(0.0, 0.62, 300, 300, 320, 240);
  const Eucm eucm_beta1(0.62, 1.0, 300, 300, 320, 240);
  const OmniRadtan mei_xi0(0.0, f, f, 320, 240);
  const PinholeRadtan pinhole(f, f, 320, 240);
  const Equidistant ideal(f, f, 320, 240, 0, 0, 0, 0);
  // Up to 125 deg: DS's published validity bound (z > -w2 d1) is conservative, for
  // alpha = 0 it stops at acos(-xi / sqrt(1 + xi^2)) = 128.7 deg, short of Mei's 143 deg.
  for (double theta_deg = 0; theta_deg < 125; theta_deg += 5) {
    for (double phi = 0.2; phi < 6.3; phi += 0.9) {
      const Eigen::Vector3d p = 1.7 * ray_at(theta_deg * kDeg, phi);
      const Eigen::Vector2d a = px(mei, p.x(), p.y(), p.z());
      EXPECT_LT((px(ds_as_mei, p.x(), p.y(), p.z()) - a).norm(), 1e-9) << theta_deg;
      EXPECT_LT((px(eucm_as_mei, p.x(), p.y(), p.z()) - a).norm(), 1e-9) << theta_deg;
      EXPECT_LT((px(ds_xi0, p.x(), p.y(), p.z()) - px(eucm_beta1, p.x(), p.y(), p.z())).norm(), 1e-9) << theta_deg;
      const Eigen::Vector2d e = px(ideal, p.x(), p.y(), p.z());
      EXPECT_NEAR((e - Eigen::Vector2d(320, 240)).norm(), f * theta_deg * kDeg, 1e-9);
      if (theta_deg < 85) {
        EXPECT_LT((px(mei_xi0, p.x(), p.y(), p.z()) - px(pinhole, p.x(), p.y(), p.z())).norm(), 1e-9) << theta_deg;
      }
    }
  }
}

}  // namespace
}  // namespace omniview
