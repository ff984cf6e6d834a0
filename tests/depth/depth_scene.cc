#include "depth_scene.h"

#include <cmath>
#include <cstdlib>
#include <limits>

#include <opencv2/core.hpp>

#include "cloud_scene.h"
#include "core/io/image_codec.h"
#include "core/map/apply.h"
#include "core/view/view.h"

namespace omniview::test {

using synthetic::Box;
using synthetic::Cylinder;
using synthetic::Material;
using synthetic::Plane;

synthetic::Scene furnished_room() {
  synthetic::Scene s;
  // Plain texture over distinct bases (no grid lines: one ray per pixel must not alias).
  const auto look = [](double b, double g, double r) { return Material{.texture_contrast = 0.5, .base = Vec3(b, g, r)}; };
  s.add(Plane{Vec3::UnitZ(), 0.0}, look(80, 120, 165));      // floor
  s.add(Plane{Vec3::UnitX(), 5.5}, look(190, 150, 110));     // front wall
  s.add(Plane{Vec3::UnitX(), -5.0}, look(120, 170, 130));    // back wall
  s.add(Plane{Vec3::UnitY(), 5.0}, look(100, 130, 200));     // left wall
  s.add(Plane{Vec3::UnitY(), -5.0}, look(170, 200, 215));    // right wall
  // No ceiling: the bird's-eye view looks down from above it.
  // Pillars and boxes 0.8 .. 4 m from the robot, of heights below and above the cameras.
  s.add(Cylinder{Vec3(2.2, 1.0, 0), 0.25, 0.0, 3.0}, look(165, 165, 165));
  s.add(Cylinder{Vec3(1.3, -1.4, 0), 0.2, 0.0, 3.0}, look(60, 60, 200));
  s.add(Cylinder{Vec3(-2.0, 1.8, 0), 0.3, 0.0, 3.0}, look(200, 80, 60));
  s.add(Box{Vec3(1.3, -0.35, 0), Vec3(1.8, 0.35, 0.8)}, look(50, 90, 140));     // a crate ahead
  s.add(Box{Vec3(3.0, 1.6, 0), Vec3(3.8, 2.6, 1.1)}, look(60, 160, 60));        // front left
  s.add(Box{Vec3(3.2, -2.6, 0), Vec3(3.9, -1.5, 1.5)}, look(140, 60, 140));     // front right, tall
  s.add(Box{Vec3(-1.6, -2.4, 0), Vec3(-0.9, -1.7, 0.6)}, look(40, 180, 200));   // behind right
  s.add(Box{Vec3(0.2, 1.4, 0), Vec3(0.9, 2.0, 0.5)}, look(180, 180, 60));       // left, low
  return s;
}

Pose T_world_body() { return make_pose(Vec3(0, 0, 0.5), 0, 0, 0); }

std::shared_ptr<Rig> ring_of_four() {
  auto rig = std::make_shared<Rig>("body");
  const double d = M_PI / 180;
  const char* names[] = {"front", "left", "back", "right"};
  for (int k = 0; k < 4; ++k) {
    Camera c;
    c.name = names[k];
    c.model = CameraModel(PinholeRadtan(250, 250, 319.5, 239.5));
    c.width = 640;
    c.height = 480;
    const double yaw = 90.0 * k * d;
    c.T_parent_cam = make_pose(Vec3(0.3 * std::cos(yaw), 0.3 * std::sin(yaw), 0.1), yaw, 20 * d, 0);
    c.T_parent_cam.linear() = c.T_parent_cam.linear() * R_view_optical();
    rig->add_camera(c);
  }
  rig->add_frame("lidar", "body", T_body_lidar());
  rig->add_frame("world", "body", T_world_body().inverse());
  return rig;
}

ViewSpec birdseye_spec(const std::string& name) {
  ViewSpec v;
  v.name = name;
  v.type = ViewType::kBirdseye;
  v.width = v.height = 400;
  v.pitch_deg = 90;
  v.height_m = 4;
  v.ground_z = -0.5;  // the floor, in the body frame
  v.hfov_deg = 100;
  return v;
}

ViewSpec front_spec(const std::string& name) {
  ViewSpec v;
  v.name = name;
  v.type = ViewType::kPerspective;
  v.width = 512;
  v.height = 256;
  v.position = Vec3(0.42, 0, 0.02);
  v.pitch_deg = 27;
  v.hfov_deg = 100;
  v.distance = 3;
  v.ground = true;
  v.ground_z = -0.5;
  return v;
}

ViewSpec panorama_spec(const std::string& name) {
  ViewSpec v;
  v.name = name;
  v.type = ViewType::kEquirectangular;
  v.width = 720;
  v.height = 240;
  v.fov_deg = 360;
  v.lat_min_deg = -60;
  v.lat_max_deg = 30;
  v.radius = 3;
  v.ground = true;
  v.ground_z = -0.5;
  return v;
}

ViewTruth view_truth(const synthetic::Scene& scene, const Rig& rig, const ViewSpec& spec) {
  const auto view = View::create(spec);
  const std::string frame = spec.frame.empty() ? rig.default_frame() : spec.frame;
  const Pose T_world_view = rig.frames().lookup("world", frame) * spec.T_frame_view();
  const Visibility visibility(scene, rig);
  ViewTruth t;
  t.grey = cv::Mat(spec.height, spec.width, CV_8UC1, cv::Scalar(0));
  t.seen = cv::Mat(spec.height, spec.width, CV_8UC1, cv::Scalar(0));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  t.points.assign(size_t(spec.width) * spec.height, Eigen::Vector3f(nan, nan, nan));
  cv::parallel_for_(cv::Range(0, spec.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      for (int u = 0; u < spec.width; ++u) {
        Vec3 dir;
        if (!view->pixel_to_direction(u, v, dir)) continue;
        const auto hit = scene.intersect(T_world_view.translation(), T_world_view.linear() * dir);
        if (!hit) continue;
        const Vec3 bgr = scene.colour(*hit);
        t.grey.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(0.114 * bgr[0] + 0.587 * bgr[1] + 0.299 * bgr[2]);
        t.points[size_t(v) * spec.width + u] = (T_world_view.inverse() * hit->point).cast<float>();
        if (visibility.any_camera_sees(hit->point)) t.seen.at<uint8_t>(v, u) = 255;
      }
    }
  });
  return t;
}

DepthScore score(const FusionMap& map, const std::vector<cv::Mat>& images, const ViewTruth& truth) {
  cv::Mat out;
  apply_map(map, images, out, 1);
  // OMNIVIEW_DEPTH_DUMP=DIR: the picture over the truth over where cameras see, as PNGs
  // numbered in call order, for a person to look at.
  if (const char* dir = std::getenv("OMNIVIEW_DEPTH_DUMP")) {
    static int count = 0;
    cv::Mat stack;
    cv::vconcat(std::vector<cv::Mat>{out, truth.grey, truth.seen}, stack);
    write_image(std::string(dir) + "/depth" + std::to_string(count++) + ".png", stack);
  }
  DepthScore s;
  double error = 0;
  size_t painted = 0;
  for (int v = 0; v < out.rows; ++v) {
    for (int u = 0; u < out.cols; ++u) {
      const bool has_camera = map.primary[size_t(v) * map.width + u].cam != kNoCamera;
      if (truth.seen.at<uint8_t>(v, u)) {
        const double d = double(out.at<uint8_t>(v, u)) - truth.grey.at<uint8_t>(v, u);
        error += d * d;
        ++s.seen;
      } else {
        ++s.unseen;
        painted += has_camera;
      }
    }
  }
  const double mse = s.seen ? error / double(s.seen) : 1e9;
  s.psnr_db = 10 * std::log10(255.0 * 255.0 / std::max(mse, 1e-12));
  s.unseen_painted = s.unseen ? double(painted) / double(s.unseen) : 0;
  return s;
}

}  // namespace omniview::test
