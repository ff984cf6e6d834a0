#include "insta360_adapter/rig/lens_circle.h"

#include <cmath>
#include <cstdio>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>

namespace omniview::insta360 {
namespace {

// Algebraic (Kasa) circle fit: x^2 + y^2 + D x + E y + F = 0 in the least-squares sense.
std::optional<Circle> fit(const std::vector<cv::Point2d>& pts) {
  if (pts.size() < 3) return std::nullopt;
  Eigen::MatrixXd A(pts.size(), 3);
  Eigen::VectorXd b(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    A(i, 0) = pts[i].x;
    A(i, 1) = pts[i].y;
    A(i, 2) = 1;
    b(i) = -(pts[i].x * pts[i].x + pts[i].y * pts[i].y);
  }
  const Eigen::Vector3d s = A.colPivHouseholderQr().solve(b);
  Circle c;
  c.centre = {-s(0) / 2, -s(1) / 2};
  const double r2 = c.centre.x * c.centre.x + c.centre.y * c.centre.y - s(2);
  if (!(r2 > 0)) return std::nullopt;
  c.radius = std::sqrt(r2);
  double sum = 0;
  for (const auto& p : pts) sum += std::pow(std::hypot(p.x - c.centre.x, p.y - c.centre.y) - c.radius, 2);
  c.rms_px = std::sqrt(sum / pts.size());
  c.edge_points = int(pts.size());
  return c;
}

}  // namespace

std::optional<Circle> find_lens_circle(const cv::Mat& image, const cv::Rect& roi) {
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image(roi), grey, cv::COLOR_BGR2GRAY);
  } else {
    grey = image(roi).clone();
  }
  cv::GaussianBlur(grey, grey, cv::Size(5, 5), 0);
  const cv::Point2d mid((grey.cols - 1) / 2.0, (grey.rows - 1) / 2.0);
  const double half = std::min(grey.cols, grey.rows) / 2.0;
  // What "bright" means: a fraction of the disc's typical level near the centre.
  cv::Mat centre_mask = cv::Mat::zeros(grey.size(), CV_8UC1);
  cv::circle(centre_mask, cv::Point(int(mid.x), int(mid.y)), int(half * 0.5), 255, -1);
  const double level = cv::mean(grey, centre_mask)[0];
  const double threshold = std::max(10.0, 0.3 * level);
  if (level < 20) return std::nullopt;  // too dark to tell the disc from the black around it

  // From the rim of the rectangle inward along 360 rays: the first bright pixel is the
  // circle's edge (dark things inside the picture never matter this way).
  std::vector<cv::Point2d> rim;
  const double outer = std::hypot(grey.cols, grey.rows) / 2;
  for (int k = 0; k < 360; ++k) {
    const double a = k * M_PI / 180, dx = std::cos(a), dy = std::sin(a);
    double r = outer;
    bool started_dark = false, found = false;
    for (; r > half * 0.3; r -= 0.5) {
      const double x = mid.x + r * dx, y = mid.y + r * dy;
      if (x < 0 || y < 0 || x > grey.cols - 1 || y > grey.rows - 1) continue;
      const double v = grey.at<uint8_t>(int(std::lround(y)), int(std::lround(x)));
      if (!started_dark) {
        if (v >= threshold) break;  // bright at the rectangle's border: the circle is clipped here
        started_dark = true;
        continue;
      }
      if (v >= threshold) {
        found = true;
        break;
      }
    }
    if (found) rim.emplace_back(mid.x + (r + 0.25) * dx, mid.y + (r + 0.25) * dy);
  }
  auto circle = fit(rim);
  if (!circle) return std::nullopt;
  // Once more without the rays that hit something else (a bright object at the rim).
  std::vector<cv::Point2d> inliers;
  for (const auto& p : rim) {
    if (std::abs(std::hypot(p.x - circle->centre.x, p.y - circle->centre.y) - circle->radius) < 3) inliers.push_back(p);
  }
  if (inliers.size() < 60) return std::nullopt;  // a rim seen over less than ~60 deg says little
  return fit(inliers);
}

LensCircleReport check_lens_circle(const Camera& camera, const cv::Mat& image, const cv::Rect& roi, int scale) {
  LensCircleReport r;
  r.camera = camera.name;
  const ModelSpec spec = describe(camera.model);
  const size_t n = spec.intrinsics.size();
  r.principal_point = {spec.intrinsics[n - 2], spec.intrinsics[n - 1]};
  if (camera.fov_deg > 0) {
    const double theta = camera.fov_deg / 2 * M_PI / 180;
    Eigen::Vector2d uv;
    if (project(camera.model, Eigen::Vector3d(std::sin(theta), 0, std::cos(theta)), uv)) {
      r.expected_radius_px = std::hypot(uv.x() - r.principal_point.x, uv.y() - r.principal_point.y);
    }
  }
  const auto circle = find_lens_circle(image, roi);
  if (!circle) return r;
  r.found = true;
  // Back to full-resolution pixels (pixel centres at integers).
  r.circle_centre = {(circle->centre.x + 0.5) * scale - 0.5, (circle->centre.y + 0.5) * scale - 0.5};
  r.radius_px = circle->radius * scale;
  r.offset_px = std::hypot(r.circle_centre.x - r.principal_point.x, r.circle_centre.y - r.principal_point.y);
  return r;
}

std::string describe(const LensCircleReport& r) {
  char buf[256];
  if (!r.found) {
    std::snprintf(buf, sizeof buf, "%s: no lens circle found (scene too dark, or the circle fills the image)",
                  r.camera.c_str());
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%s: lens circle centre %.1f px from the principal point (%+.1f, %+.1f); radius %.0f px",
                r.camera.c_str(), r.offset_px, r.circle_centre.x - r.principal_point.x,
                r.circle_centre.y - r.principal_point.y, r.radius_px);
  std::string s = buf;
  if (r.expected_radius_px > 0) {
    std::snprintf(buf, sizeof buf, " (calibrated %.0f)", r.expected_radius_px);
    s += buf;
  }
  return s;
}

}  // namespace omniview::insta360
