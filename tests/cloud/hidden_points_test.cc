// Occlusion in cloud colouring, measured as issue 32 sets it: a dense cloud of what a lidar
// sees plus, for every such point, one 0.4-0.8 m further along the same ray, where no camera
// can see it (checked by ray casting: only points no camera sees count as hidden, only points
// some camera sees as visible). The colourer (default options, occlusion on) should leave the
// hidden ones uncoloured and colour the visible ones. Two clouds: a lidar's rays ~1 deg
// apart (360 points/m² at 3 m, more nearer), and the same thinned to one point per 5 cm
// voxel (~400 points/m² on the walls and floor, whatever the range: the 260-450).
// Two rigs: Spot's five cameras in the furnished room, and two back-to-back 210 deg fisheyes
// (an Insta360 Air) inside a sphere of 4 m.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <unordered_set>

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
// the surface points they hit, and behind each one a point 0.4-0.8 m further on. With
// `voxel_m`, only the first hit in each voxel of that size is kept (a voxel filter).
void sample_cloud(const synthetic::Scene& scene, const Vec3& origin, double step_deg, double el_min, double el_max,
                  double voxel_m, std::vector<Vec3>& surface, std::vector<Vec3>& behind) {
  size_t k = 0;
  std::unordered_set<int64_t> taken;
  auto first_in_voxel = [&](const Vec3& p) {
    int64_t key = 0;
    for (int a = 0; a < 3; ++a) key = key * 100003 + static_cast<int64_t>(std::floor(p[a] / voxel_m) + 50000);
    return taken.insert(key).second;
  };
  for (double el = el_min; el <= el_max; el += step_deg) {
    // Fewer azimuths towards the poles keep the spacing on a sphere even.
    const double az_step = step_deg / std::max(0.2, std::cos(el * M_PI / 180));
    for (double az = -180; az < 180; az += az_step, ++k) {
      const double e = el * M_PI / 180, a = az * M_PI / 180;
      const Vec3 dir(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      const auto hit = scene.intersect(origin, dir);
      if (!hit || (voxel_m > 0 && !first_in_voxel(hit->point))) continue;
      surface.push_back(hit->point);
      const double depth = 0.4 + 0.4 * double((k * 7919) % 1000) / 1000.0;  // spread evenly over 0.4-0.8 m
      behind.push_back(hit->point + depth * dir);
    }
  }
}

Shares measure(const std::shared_ptr<Rig>& rig, const synthetic::Scene& scene, const Vec3& lidar_world,
               double el_min, double el_max, const std::string& name, double voxel_m = 0) {
  std::vector<Vec3> surface, behind;
  // Voxels: rays 0.2 deg apart, so that every voxel on a surface gets one.
  sample_cloud(scene, lidar_world, voxel_m > 0 ? 0.2 : 1.0, el_min, el_max, voxel_m, surface, behind);
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

// The goals hold: Spot 99.7 % of the visible points coloured and 1.1 % of the
// hidden ones, the fisheyes 100 % and 0.2 %. Before stop 38, 99.7 % / 1.9 % and 100 % /
// 25 %: the hidden_behind tolerance was 10 % of the range + 0.1 m, 0.5 m at 4 m, so most
// points less than 0.5 m behind the sphere took its colour (the 24 %; a sphere of
// 3 m, where that tolerance is exactly 0.4 m, showed 0.4 %). That tolerance was there for
// surfaces seen at a slant, whose covering depth came out up to one cell's depth change
// nearer than the surface; the covering depth now allows for that itself (camera_pass.cc,
// occluding_depth) and the tolerance is 3 % + 0.08 m. Earlier, 1 deg cells (stop 37) had
// left 4.6 % of Spot's hidden points coloured, below the floor near the robot.
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

// The same room with the cloud thinned to one point per 5 cm voxel: 99.2 % of the visible
// points coloured, 1.95 % of the hidden ones (before the covering depth allowed for a slant:
// 98.9 % / 3.2 %), just inside the goal. What is left lies 1-2 m from the
// cameras (the floor near the robot): 5 cm apart there is 1.5-6 deg as a camera sees it,
// more than the depth buffer's 4 deg reach, so a cell with hidden points often has no
// surface sample within reach on one side, or only other hidden points.
TEST(HiddenPoints, SpotsFiveCamerasInTheRoomVoxelCloud) {
  const Pose T_world_body = make_pose(Vec3(0.5, 0.3, 0.5), 0.2, 0, 0);
  const auto rig = test::rig_in_world(T_world_body);
  const Vec3 lidar = (T_world_body * test::T_body_lidar()).translation();
  const Shares s = measure(rig, synthetic::Scene::room(), lidar, -89, 89, "Spot, room, 5 cm voxels", 0.05);
  ASSERT_GT(s.visible, 10000u);
  ASSERT_GT(s.hidden, 10000u);
  EXPECT_GE(s.visible_share(), 0.98);
  EXPECT_LE(s.hidden_share(), 0.02);
}

TEST(HiddenPoints, TwoFisheyesInASphere) {
  auto rig = std::make_shared<Rig>(load_rig(OMNIVIEW_SOURCE_DIR "/config/examples/dual_fisheye/rig.yaml"));
  rig->add_frame("world", rig->default_frame(), Pose::Identity());
  const Vec3 lidar(0, 0, 1.3);  // above the lenses (1 m above base_link)
  const Shares s = measure(rig, synthetic::Scene::sphere(4, Vec3(0, 0, 1)), lidar, -80, 80, "two fisheyes, sphere");
  ASSERT_GT(s.visible, 10000u);
  ASSERT_GT(s.hidden, 10000u);
  EXPECT_GE(s.visible_share(), 0.98);
  EXPECT_LE(s.hidden_share(), 0.02);
}

}  // namespace
}  // namespace omniview
