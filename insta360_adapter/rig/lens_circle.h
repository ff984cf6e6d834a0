// The lens-circle check: finds each fisheye's image circle (the bright disc the lens
// throws on the sensor, black around it) in a live frame and compares its centre with the
// calibration's principal point. A cheap dual fisheye whose lens sits a few pixels off its
// nominal calibration shows it here, in the source's status and `omniview cameras`.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/camera/camera.h"

namespace omniview::insta360 {

struct Circle {
  cv::Point2d centre;
  double radius = 0;
  int edge_points = 0;  // rays that found the rim
  double rms_px = 0;    // of the rim points about the fitted circle
};

// The image circle inside `roi` of `image` (BGR or grey), in `roi`'s pixel coordinates;
// nullopt when no rim is found (a lens whose circle fills its whole rectangle, a dark
// scene). Rays from the centre outward that never leave the bright disc are ignored.
std::optional<Circle> find_lens_circle(const cv::Mat& image, const cv::Rect& roi);

struct LensCircleReport {
  std::string camera;
  bool found = false;
  cv::Point2d principal_point;   // calibrated (lens-image pixels, full resolution)
  cv::Point2d circle_centre;     // detected
  double offset_px = 0;          // |centre - principal point|
  double radius_px = 0;          // detected
  double expected_radius_px = 0; // where the calibration puts the rim (fov_deg / 2), 0 if unknown
};
// "front: circle centre 5.1 px from the principal point (+4.9, -1.3); radius 733 px (calibrated 735)"
std::string describe(const LensCircleReport& report);

// Checks `camera` (its calibration in lens-image pixels) against the circle found in
// `roi` of `image`, which may be decoded at 1/scale.
LensCircleReport check_lens_circle(const Camera& camera, const cv::Mat& image, const cv::Rect& roi, int scale = 1);

// The offset above which the status calls a lens off its calibration.
inline constexpr double kLensOffsetWarnPx = 3.0;

}  // namespace omniview::insta360
