// Agreement with OpenCV's independent implementations: cv::projectPoints (pinhole +
// 5-coefficient plumb_bob), cv::fisheye::projectPoints (Kannala-Brandt; z > 0 only, since
// OpenCV takes theta = atan(r / z)) and cv::omnidir::projectPoints (Mei + radtan).
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/ccalib/omnidir.hpp>

#include "core/camera/camera_model.h"
#include "core/geometry/pose.h"
#include "test_support.h"

namespace omniview {
namespace {

using testing::kDeg;

// Points on a dense grid of directions up to `max_angle_deg` off the axis, at varying range.
std::vector<cv::Point3d> points_in_front(double max_angle_deg) {
  std::vector<cv::Point3d> pts;
  int i = 0;
  for (double t = 0; t <= max_angle_deg; t += 2) {
    for (double p = 3; p < 360; p += 10, ++i) {
      const Eigen::Vector3d q = (0.5 + (i % 7)) * testing::ray_at(t * kDeg, p * kDeg);
      pts.emplace_back(q.x(), q.y(), q.z());
    }
  }
  return pts;
}

// Our projection of T_cam_world * p against OpenCV's with the same rvec, tvec.
void expect_same(const CameraModel& model, const Pose& T_cam_world, const std::vector<cv::Point3d>& pts,
                 const std::vector<cv::Point2d>& ref, double tol = 1e-6) {
  ASSERT_EQ(pts.size(), ref.size());
  double worst = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(project(model, T_cam_world * Eigen::Vector3d(pts[i].x, pts[i].y, pts[i].z), uv)) << i;
    worst = std::max(worst, (uv - Eigen::Vector2d(ref[i].x, ref[i].y)).norm());
  }
  EXPECT_LT(worst, tol) << "px over " << pts.size() << " points";
}

cv::Vec3d rvec_of(const Pose& T) {
  cv::Matx33d R;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R(r, c) = T.linear()(r, c);
  }
  cv::Vec3d r;
  cv::Rodrigues(R, r);
  return r;
}

TEST(OpenCvAgreement, PinholeRadtanFiveCoefficientsMatchesProjectPoints) {
  const cv::Matx33d K(461.6, 0, 366.2, 0, 460.3, 249.1, 0, 0, 1);
  const std::vector<double> D{-0.27, 0.06, 0.0007, -0.0004, -0.004};
  const auto pts = points_in_front(50);
  std::vector<cv::Point2d> ref;
  cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, ref);
  expect_same(make_camera_model({"pinhole", "radtan", {461.6, 460.3, 366.2, 249.1}, D}, "test"), Pose::Identity(), pts,
              ref);
}

TEST(OpenCvAgreement, PinholeRadtanFourCoefficientsWithAPose) {
  // Also pins the pose convention: OpenCV maps world to camera with (rvec, tvec), which is
  // our T_cam_world.
  const cv::Matx33d K(458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1);
  const std::vector<double> D{-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  const Pose T_cam_world = make_pose(Vec3(0.1, -0.2, 0.3), 0.05, -0.08, 0.1);
  std::vector<cv::Point3d> pts;
  for (const auto& p : points_in_front(40)) {
    const Eigen::Vector3d q = T_cam_world.inverse() * Eigen::Vector3d(p.x, p.y, p.z + 1.0);
    pts.emplace_back(q.x(), q.y(), q.z());
  }
  const Eigen::Vector3d t = T_cam_world.translation();
  std::vector<cv::Point2d> ref;
  cv::projectPoints(pts, rvec_of(T_cam_world), cv::Vec3d(t.x(), t.y(), t.z()), K, D, ref);
  expect_same(make_camera_model({"pinhole", "radtan", {458.654, 457.296, 367.215, 248.375}, D}, "test"), T_cam_world,
              pts, ref);
}

TEST(OpenCvAgreement, PinholeRadtanUnprojectMatchesUndistortPoints) {
  const cv::Matx33d K(461.6, 0, 366.2, 0, 460.3, 249.1, 0, 0, 1);
  const std::vector<double> D{-0.27, 0.06, 0.0007, -0.0004, -0.004};
  const CameraModel model = make_camera_model({"pinhole", "radtan", {461.6, 460.3, 366.2, 249.1}, D}, "test");
  std::vector<cv::Point2d> pixels, normalised;
  for (int v = 0; v < 480; v += 24) {
    for (int u = 0; u < 752; u += 24) pixels.emplace_back(u, v);
  }
  // OpenCV's default is 5 fixed-point iterations; ask for convergence instead.
  cv::undistortPoints(pixels, normalised, K, D, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-15));
  for (size_t i = 0; i < pixels.size(); ++i) {
    Eigen::Vector3d ray;
    ASSERT_TRUE(unproject(model, {pixels[i].x, pixels[i].y}, ray)) << pixels[i];
    EXPECT_NEAR(ray.x() / ray.z(), normalised[i].x, 1e-8) << pixels[i];
    EXPECT_NEAR(ray.y() / ray.z(), normalised[i].y, 1e-8) << pixels[i];
  }
}

TEST(OpenCvAgreement, EquidistantMatchesFisheyeProjectPointsInFront) {
  // The 210 deg lens of the examples and TUM VI's calibration. OpenCV's atan(r / z) only
  // holds for z > 0, so the points stop short of 90 deg.
  for (const auto& [K, D] : std::vector<std::pair<cv::Matx33d, cv::Vec4d>>{
           {cv::Matx33d(258, 0, 511.5, 0, 259, 512.5, 0, 0, 1), cv::Vec4d(0.02, -0.004, 0.0005, -0.0001)},
           {cv::Matx33d(190.97847715128717, 0, 254.93170605935475, 0, 190.9733070521226, 256.8974428996504, 0, 0, 1),
            cv::Vec4d(0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182)}}) {
    const auto pts = points_in_front(88);
    std::vector<cv::Point2d> ref;
    cv::fisheye::projectPoints(pts, ref, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D);
    expect_same(make_camera_model(
                    {"pinhole", "equidistant", {K(0, 0), K(1, 1), K(0, 2), K(1, 2)}, {D[0], D[1], D[2], D[3]}}, "t"),
                Pose::Identity(), pts, ref);
  }
}

TEST(OpenCvAgreement, EquidistantUnprojectMatchesFisheyeUndistortPoints) {
  const cv::Matx33d K(258, 0, 511.5, 0, 259, 512.5, 0, 0, 1);
  const cv::Vec4d D(0.02, -0.004, 0.0005, -0.0001);
  const CameraModel model =
      make_camera_model({"pinhole", "equidistant", {258, 259, 511.5, 512.5}, {D[0], D[1], D[2], D[3]}}, "t");
  // Pixels inside the 80 deg circle (OpenCV returns x/z, meaningless past 90 deg).
  std::vector<cv::Point2d> pixels, normalised;
  for (int v = 100; v < 925; v += 25) {
    for (int u = 100; u < 925; u += 25) {
      Eigen::Vector3d ray;
      if (unproject(model, {double(u), double(v)}, ray) && ray.z() > std::cos(80 * kDeg)) pixels.emplace_back(u, v);
    }
  }
  ASSERT_GT(pixels.size(), 500u);
  cv::fisheye::undistortPoints(pixels, normalised, K, D);
  for (size_t i = 0; i < pixels.size(); ++i) {
    Eigen::Vector3d ray;
    ASSERT_TRUE(unproject(model, {pixels[i].x, pixels[i].y}, ray));
    // OpenCV's fixed 10 Newton steps in float-ish tolerance: agree to 1e-6 in x/z.
    EXPECT_NEAR(ray.x() / ray.z(), normalised[i].x, 1e-6) << pixels[i];
    EXPECT_NEAR(ray.y() / ray.z(), normalised[i].y, 1e-6) << pixels[i];
  }
}

TEST(OpenCvAgreement, OmniRadtanMatchesOmnidirProjectPoints) {
  // cv::omnidir takes k1 k2 p1 p2 (no k3). Beyond 90 deg too: Mei has no z > 0 limit.
  for (const double xi : {0.9, 1.6}) {
    const cv::Matx33d K(700, 0, 320, 0, 701, 240, 0, 0, 1);
    const cv::Matx14d D(-0.28, 0.07, 0.0007, -0.0004);
    const auto pts = points_in_front(xi < 1 ? 110 : 100);
    std::vector<cv::Point2d> ref;
    cv::omnidir::projectPoints(pts, ref, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, xi, D);
    expect_same(make_camera_model({"omni", "radtan", {xi, 700, 701, 320, 240}, {D(0), D(1), D(2), D(3)}}, "t"),
                Pose::Identity(), pts, ref);
  }
}

TEST(OpenCvAgreement, OmniRadtanWithAPose) {
  const cv::Matx33d K(520, 0, 319.5, 0, 521, 239.5, 0, 0, 1);
  const cv::Matx14d D(-0.12, 0.03, 0.0004, -0.0002);
  const Pose T_cam_world = make_pose(Vec3(-0.3, 0.1, 0.2), 0.3, 0.2, -0.1);
  std::vector<cv::Point3d> pts;
  for (const auto& p : points_in_front(100)) {
    const Eigen::Vector3d q = T_cam_world.inverse() * Eigen::Vector3d(p.x, p.y, p.z);
    pts.emplace_back(q.x(), q.y(), q.z());
  }
  const Eigen::Vector3d t = T_cam_world.translation();
  std::vector<cv::Point2d> ref;
  cv::omnidir::projectPoints(pts, ref, rvec_of(T_cam_world), cv::Vec3d(t.x(), t.y(), t.z()), K, 1.1, D);
  expect_same(make_camera_model({"omni", "radtan", {1.1, 520, 521, 319.5, 239.5}, {D(0), D(1), D(2), D(3)}}, "t"),
              T_cam_world, pts, ref);
}

}  // namespace
}  // namespace omniview
