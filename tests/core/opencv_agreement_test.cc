// Agreement with OpenCV's independent implementations: cv::projectPoints (pinhole +
// 5-coefficient radtan), cv::fisheye::projectPoints (Kannala-Brandt, z > 0 only: OpenCV
// uses atan(r / z)) and cv::omnidir::projectPoints (Mei + radtan).
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/ccalib/omnidir.hpp>

#include "core/camera/camera_model.h"

namespace omniview {
namespace {

std::vector<cv::Point3d> points_in_front(double max_angle_deg) {
  std::vector<cv::Point3d> pts;
  for (double t = 0; t <= max_angle_deg; t += 4) {
    for (double p = 0; p < 360; p += 20) {
      const double th = t * M_PI / 180, ph = p * M_PI / 180;
      pts.emplace_back(2 * std::sin(th) * std::cos(ph), 2 * std::sin(th) * std::sin(ph), 2 * std::cos(th));
    }
  }
  return pts;
}

void expect_same(const CameraModel& model, const std::vector<cv::Point3d>& pts, const std::vector<cv::Point2d>& ref) {
  ASSERT_EQ(pts.size(), ref.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(project(model, {pts[i].x, pts[i].y, pts[i].z}, uv)) << i;
    EXPECT_NEAR(uv.x(), ref[i].x, 1e-6) << i;
    EXPECT_NEAR(uv.y(), ref[i].y, 1e-6) << i;
  }
}

TEST(OpenCvAgreement, PinholeRadtanMatchesProjectPoints) {
  const cv::Matx33d K(461.6, 0, 366.2, 0, 460.3, 249.1, 0, 0, 1);
  const std::vector<double> D{-0.27, 0.06, 0.0007, -0.0004, -0.004};
  const auto pts = points_in_front(45);
  std::vector<cv::Point2d> ref;
  cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, ref);
  expect_same(make_camera_model({"pinhole", "radtan", {461.6, 460.3, 366.2, 249.1}, D}, "test"), pts, ref);
}

TEST(OpenCvAgreement, EquidistantMatchesFisheyeProjectPoints) {
  const cv::Matx33d K(258, 0, 511.5, 0, 259, 512.5, 0, 0, 1);
  const cv::Vec4d D(0.02, -0.004, 0.0005, -0.0001);
  const auto pts = points_in_front(88);
  std::vector<cv::Point2d> ref;
  cv::fisheye::projectPoints(pts, ref, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D);
  expect_same(make_camera_model({"pinhole", "equidistant", {258, 259, 511.5, 512.5}, {D[0], D[1], D[2], D[3]}}, "t"),
              pts, ref);
}

TEST(OpenCvAgreement, OmniRadtanMatchesOmnidirProjectPoints) {
  const cv::Matx33d K(700, 0, 320, 0, 701, 240, 0, 0, 1);
  const cv::Matx14d D(-0.28, 0.07, 0.0007, -0.0004);  // cv::omnidir takes k1 k2 p1 p2
  const double xi = 0.9;
  const auto pts = points_in_front(60);
  std::vector<cv::Point2d> ref;
  cv::omnidir::projectPoints(pts, ref, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, xi, D);
  expect_same(make_camera_model({"omni", "radtan", {xi, 700, 701, 320, 240}, {D(0), D(1), D(2), D(3)}}, "t"), pts,
              ref);
}

}  // namespace
}  // namespace omniview
