// The rendered robot lands exactly where the view's pinhole puts it: the body box's
// silhouette against the convex hull of its projected corners, for several view poses.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/robot/model/urdf_loader.h"
#include "core/robot/render/gl_projection.h"
#include "core/robot/render/offscreen_renderer.h"
#include "robot_test_support.h"

namespace omniview::robot {
namespace {

using test::alpha_mask;
using test::project;

// A view looking along (yaw, pitch, roll) at `target` from `range` metres away.
ViewSpec view_at(const Vec3& target, double range, double yaw, double pitch, double roll) {
  const Vec3 forward = rotation_from_ypr(yaw * M_PI / 180, pitch * M_PI / 180, roll * M_PI / 180) * Vec3::UnitX();
  const Vec3 eye = target - range * forward;
  ViewSpec s = test::birdseye_view(200, 150, 70, eye.x(), eye.y(), eye.z(), yaw, pitch);
  s.roll_deg = roll;
  return s;
}

TEST(GlProjection, PixelCentresLandOnHalfIntegerWindowCoordinates) {
  const PinholeCamera c{64, 48, 50, 55, 31.5, 23.5};
  const Eigen::Matrix4d P = gl_projection(c, 0.1, 10);
  for (const Vec3& p : {Vec3(0, 0, 1), Vec3(0.3, -0.2, 2), Vec3(-0.5, 0.4, 5)}) {
    const Eigen::Vector4d clip = P * p.homogeneous();
    const Vec2 window((clip.x() / clip.w() + 1) * c.width / 2, (clip.y() / clip.w() + 1) * c.height / 2);
    const Vec2 uv = c.project(p);
    EXPECT_NEAR(window.x(), uv.x() + 0.5, 1e-9);
    EXPECT_NEAR(window.y(), uv.y() + 0.5, 1e-9);  // not flipped: window row = image row
  }
  const Eigen::Vector4d near = P * Vec3(0, 0, 0.1).homogeneous(), far = P * Vec3(0, 0, 10).homogeneous();
  EXPECT_NEAR(near.z() / near.w(), -1, 1e-12);
  EXPECT_NEAR(far.z() / far.w(), 1, 1e-12);
}

TEST(PinholeCameraOfView, FollowsTheConventions) {
  const ViewSpec s = test::birdseye_view(200, 150, 90, 0, 0, 3, 0, 90);
  const PinholeCamera c = pinhole_camera_of(s);
  EXPECT_DOUBLE_EQ(c.fx, 100);
  EXPECT_DOUBLE_EQ(c.cx, 99.5);
  EXPECT_DOUBLE_EQ(c.cy, 74.5);
  // Straight down: the robot's front at the top of the image, its left on the left.
  const auto px = project(c, T_frame_optical(s), {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)});
  EXPECT_NEAR(px[0].x, 99.5, 1e-4);
  EXPECT_NEAR(px[0].y, 74.5, 1e-4);
  EXPECT_NEAR(px[1].y, 74.5 - 100.0 / 3, 1e-4);
  EXPECT_NEAR(px[2].x, 99.5 - 100.0 / 3, 1e-4);
}

struct NamedView {
  const char* name;
  ViewSpec spec;
};
void PrintTo(const NamedView& v, std::ostream* os) { *os << v.name; }

class BodyBox : public ::testing::TestWithParam<NamedView> {
 protected:
  static void SetUpTestSuite() { model_ = std::make_unique<RobotModel>(load_urdf_file(test::spot_urdf())); }
  static void TearDownTestSuite() { model_.reset(); }

  // The body link's first visual: the box of the URDF.
  const Visual& body_box() const {
    const int body = model_->link_index("body");
    for (const auto& v : model_->visuals()) {
      if (v.link == body) return v;
    }
    throw std::logic_error("no body visual");
  }

  static std::unique_ptr<RobotModel> model_;
};
std::unique_ptr<RobotModel> BodyBox::model_;

TEST_P(BodyBox, SilhouetteIsTheHullOfTheProjectedCorners) {
  const Visual& box = body_box();
  Eigen::Vector3f lo = box.mesh.positions[0], hi = lo;
  for (const auto& p : box.mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  ASSERT_TRUE((hi - lo).isApprox(Eigen::Vector3f(0.87f, 0.25f, 0.17f), 1e-6f)) << (hi - lo).transpose();
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) corners.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());

  const ViewSpec& spec = GetParam().spec;
  const PinholeCamera camera = pinhole_camera_of(spec);
  const Pose T_robot_camera = T_frame_optical(spec);
  OffscreenRenderer renderer;
  const cv::Mat image = renderer.render({{&box.mesh, Pose::Identity()}}, camera, T_robot_camera);
  ASSERT_EQ(image.type(), CV_8UC4);
  ASSERT_EQ(image.size(), cv::Size(camera.width, camera.height));
  const cv::Mat mask = alpha_mask(image);
  const auto pixels = project(camera, T_robot_camera, corners);

  // Every corner's pixel is covered, or a pixel next to it (the corner sits on the edge).
  for (const auto& px : pixels) {
    ASSERT_TRUE(px.x > 2 && px.y > 2 && px.x < camera.width - 3 && px.y < camera.height - 3) << "corner out of view";
    bool covered = false;
    for (int dv = -1; dv <= 1; ++dv) {
      for (int du = -1; du <= 1; ++du) covered |= mask.at<uint8_t>(int(std::lround(px.y)) + dv, int(std::lround(px.x)) + du) != 0;
    }
    EXPECT_TRUE(covered) << "corner at " << px;
  }
  // The silhouette is exactly the pixels whose centres lie inside the hull: a half-pixel
  // shift or a flip would put whole rows and columns of pixels on the wrong side.
  EXPECT_EQ(test::hull_disagreements(mask, pixels, 0.02), 0);
  cv::Mat expected, distance;
  test::hull_mask(pixels, mask.size(), expected, distance);
  const cv::Rect got = cv::boundingRect(mask), want = cv::boundingRect(expected);
  EXPECT_LE(std::abs(got.x - want.x) + std::abs(got.y - want.y) + std::abs(got.width - want.width) +
                std::abs(got.height - want.height), 1)
      << "mask extent " << got << ", projected box " << want;
}

INSTANTIATE_TEST_SUITE_P(Views, BodyBox,
                         ::testing::Values(NamedView{"straight_down", view_at(Vec3::Zero(), 2.5, 0, 90, 0)},
                                           NamedView{"tilted_30", view_at(Vec3::Zero(), 2.5, 0, 60, 0)},
                                           NamedView{"yawed_40", view_at(Vec3(0.1, -0.05, 0), 2.5, 40, 90, 0)},
                                           NamedView{"oblique_rolled", view_at(Vec3::Zero(), 2.2, -35, 50, 10)}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace omniview::robot
