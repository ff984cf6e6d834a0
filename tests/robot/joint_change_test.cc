// Moving one leg changes the rendered mask where that leg is (before or after), and
// nowhere else.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "core/robot/model/urdf_loader.h"
#include "core/robot/overlay/robot_overlay.h"
#include "robot_test_support.h"

namespace omniview::robot {
namespace {

JointPositions standing() {
  JointPositions q;
  for (const char* leg : {"fl", "fr", "hl", "hr"}) {
    q[std::string(leg) + ".hx"] = 0;
    q[std::string(leg) + ".hy"] = 0.8;
    q[std::string(leg) + ".kn"] = -1.6;
  }
  return q;
}

struct LegMove {
  const char* leg;
  const char* joint;
  double value;
  double pitch_deg;  // of the view
};
void PrintTo(const LegMove& m, std::ostream* os) { *os << m.joint << "=" << m.value << " pitch " << m.pitch_deg; }

class JointChange : public ::testing::TestWithParam<LegMove> {};

TEST_P(JointChange, ChangesTheMaskOnlyWhereTheLegIs) {
  const LegMove move = GetParam();
  auto model = std::make_shared<const RobotModel>(load_urdf_file(test::spot_urdf()));
  ViewSpec spec = test::birdseye_view(320, 240, 50, 0, 0, 2.5, 0, 90);
  if (move.pitch_deg != 90) {
    spec.pitch_deg = move.pitch_deg;
    spec.position.x() = -2.5 / std::tan(move.pitch_deg * M_PI / 180);
  }
  const PinholeCamera camera = pinhole_camera_of(spec);
  const Pose T_robot_camera = T_frame_optical(spec);

  RobotOverlay overlay(model);
  overlay.set_joint_positions(standing());
  const std::vector<double> before_q = overlay.joint_positions();
  const cv::Mat before = test::alpha_mask(overlay.layer(camera, T_robot_camera).bgra);
  overlay.set_joint_positions({{move.joint, move.value}});
  const cv::Mat after = test::alpha_mask(overlay.layer(camera, T_robot_camera).bgra);
  ASSERT_EQ(overlay.render_count(), 2);

  cv::Mat changed;
  cv::bitwise_xor(before, after, changed);
  EXPECT_GT(cv::countNonZero(changed), 30) << "the move should be visible";

  // Where the leg's links are, before and after, with a pixel of rasterisation slack.
  std::vector<cv::Point2f> leg_pixels;
  for (const auto* q : {&before_q, &overlay.joint_positions()}) {
    for (const char* part : {".hip", ".uleg", ".lleg"}) {
      const auto px = test::project(camera, T_robot_camera, test::link_vertices(*model, std::string(move.leg) + part, *q));
      leg_pixels.insert(leg_pixels.end(), px.begin(), px.end());
    }
  }
  cv::Point2f lo = leg_pixels[0], hi = lo;
  for (const auto& p : leg_pixels) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
  }
  const cv::Rect allowed(cv::Point(int(std::floor(lo.x)) - 1, int(std::floor(lo.y)) - 1),
                         cv::Point(int(std::ceil(hi.x)) + 2, int(std::ceil(hi.y)) + 2));
  std::vector<cv::Point> changed_pixels;
  cv::findNonZero(changed, changed_pixels);
  int outside = 0;
  for (const auto& p : changed_pixels) outside += !allowed.contains(p);
  EXPECT_EQ(outside, 0) << "changed pixels outside the leg's box " << allowed;
  // And the leg's box is a small part of the robot, so the check has teeth.
  EXPECT_LT(allowed.area(), cv::boundingRect(before).area() / 2);
}

INSTANTIATE_TEST_SUITE_P(Legs, JointChange,
                         ::testing::Values(LegMove{"fl", "fl.hx", 0.5, 90}, LegMove{"hr", "hr.hy", 1.6, 90},
                                           LegMove{"fr", "fr.hx", -0.5, 60}));

}  // namespace
}  // namespace omniview::robot
