// Occlusion in cloud colouring, measured as issue 32 sets it: a dense cloud of what a lidar
// sees (~1 deg apart: 360 points/m² at 3 m) plus, for every such point, one 0.4-0.8 m
// further along the same ray, where no camera can see it (checked by ray casting: only
// points no camera sees count as hidden, only points some camera sees as visible). The
// colourer (default options, occlusion on) should leave the hidden ones uncoloured and
// colour the visible ones. Two rigs: Spot's five cameras in the furnished room, and two
// back-to-back 210 deg fisheyes (an Insta360 Air) inside a sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "cloud_scene.h"
#include "core/cloud/colourer.h"

namespace omniview {
namespace {

struct Shares {
  size_t visible = 0, visible_coloured = 0;
  size_t hidden = 0, hidden_coloured = 0;
  double visible_share() const { return visible ? double(visible_coloured) / double(visible) : 0; }
  double hidden_share() const { return hidden ? double(hidden_coloured) / double(hidden) : 0; }
};

// Rays from `origin` every `step_deg` in azimuth and elevation within [el_min, el_max]:
// the surface points they hit, and behind each one a point 0.4-0.8 m further on.
void sample_cloud(const synthetic::Scene& scene, const Vec3& origin, double step_deg, double el_min, double el_max,
                  std::vector<Vec3>& surface, std::vector<Vec3>& behind) {
  size_t k = 0;
  for (double el = el_min; el <= el_max; el += step_deg) {
    // Fewer azimuths towards the poles keep the spacing on a sphere even.
    const double az_step = step_deg / std::max(0.2, std::cos(el * M_PI / 180));
    for (double az = -180; az < 180; az += az_step, ++k) {
      const double e = el * M_PI / 180, a = az * M_PI / 180;
      const Vec3 dir(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      const auto hit = scene.intersect(origin, dir);
      if (!hit) continue;
      surface.push_back(hit->point);
      const double depth = 0.4 + 0.4 * double((k * 7919) % 1000) / 1000.0;  // spread evenly over 0.4-0.8 m
      behind.push_back(hit->point + depth * dir);
    }
  }
}

Shares measure(const std::shared_ptr<Rig>& rig, const synthetic::Scene& scene, const Vec3& lidar_world,
               double el_min, double el_max, const std::string& name) {
  std::vector<Vec3> surface, behind;
  sample_cloud(scene, lidar_world, 1.0, el_min, el_max, surface, behind);
  const test::Visibility visibility(scene, *rig);
  PointCloud cloud;
  cloud.frame = "world";
  std::vector<int> kind;  // 1: visible, 2: hidden, 0: neither (not counted)
  for (const auto& p : surface) {
    cloud.points.push_back(p.cast<float>());
    kind.push_back(visibility.any_camera_sees(p) ? 1 : 0);
  }
  for (const auto& q : behind) {
    cloud.points.push_back(q.cast<float>());
    kind.push_back(visibility.any_camera_sees(q) ? 0 : 2);
  }
  CloudColourer colourer(rig);
  ColourOptions options;
  options.time_sync = false;
  colourer.colour(cloud, CameraImages{test::render_images(scene, *rig), {}}, options);
  Shares s;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const bool coloured = cloud.camera[i] != kNoCamera;
    if (kind[i] == 1) ++s.visible, s.visible_coloured += coloured;
    if (kind[i] == 2) ++s.hidden, s.hidden_coloured += coloured;
  }
  std::cout << name << ": " << cloud.size() << " points; visible " << s.visible << ", coloured "
            << 100 * s.visible_share() << " %; hidden " << s.hidden << ", coloured " << 100 * s.hidden_share()
            << " % (issue 32's goal: >= 98 % and <= 2 %)\n";
  return s;
}

// The goals hold: Spot 99.7 % of the visible points coloured and 1.9 % of the
// hidden ones, the fisheyes 100 % and 0.4 %. With the depth buffer's cells at 1 deg (before
// stop 37) Spot's cameras coloured 4.6 % of the hidden points: below the floor near the
// robot, where the camera looks down through a densely sampled floor (every one beyond
// the tolerance of the surface in front of it). Most likely the small cells left the cell
// rule (nearer samples on both sides within the reach, core/cloud/camera_pass.cc) without a
// covering sample too often; measured: 2 deg cells 1.5 %, 1.5 deg 1.9 %, 1 deg 4.6 %,
// 0.5 deg 17 %.
TEST(HiddenPoints, SpotsFiveCamerasInTheRoom) {
  const Pose T_world_body = make_pose(Vec3(0.5, 0.3, 0.5), 0.2, 0, 0);
  const auto rig = test::rig_in_world(T_world_body);
  const Vec3 lidar = (T_world_body * test::T_body_lidar()).translation();
  const Shares s = measure(rig, synthetic::Scene::room(), lidar, -89, 89, "Spot, room");
  ASSERT_GT(s.visible, 10000u);
  ASSERT_GT(s.hidden, 10000u);
  EXPECT_GE(s.visible_share(), 0.98);
  EXPECT_LE(s.hidden_share(), 0.02);
}

TEST(HiddenPoints, TwoFisheyesInASphere) {
  auto rig = std::make_shared<Rig>(load_rig(OMNIVIEW_SOURCE_DIR "/config/examples/dual_fisheye/rig.yaml"));
  rig->add_frame("world", rig->default_frame(), Pose::Identity());
  const Vec3 lidar(0, 0, 1.3);  // above the lenses (1 m above base_link)
  const Shares s = measure(rig, synthetic::Scene::sphere(3, Vec3(0, 0, 1)), lidar, -80, 80, "two fisheyes, sphere");
  ASSERT_GT(s.visible, 10000u);
  ASSERT_GT(s.hidden, 10000u);
  EXPECT_GE(s.visible_share(), 0.98);
  EXPECT_LE(s.hidden_share(), 0.02);
}

}  // namespace
}  // namespace omniview
