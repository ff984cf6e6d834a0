// Colouring on the synthetic scene: texture colours come back, occluders do not paint what
// they hide (unless occlusion is off), a walking robot is coloured right with time sync
// and wrong without, grey cameras give grey, and the robot's legs are filtered out.
#include <chrono>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "cloud_scene.h"
#include "core/cloud/colourer.h"
#include "core/cloud/self_filter.h"
#include "core/robot/model/urdf_loader.h"
#include "core/synthetic/lidar_scan.h"

namespace omniview {
namespace {

using Clock = std::chrono::system_clock;
const Clock::time_point kStamp = Clock::time_point(std::chrono::seconds(1700000000));

struct Scored {
  size_t visible = 0;       // points some camera sees (ground truth)
  size_t right = 0;         // ... coloured within 8 grey levels of the truth
  size_t wrong_colour = 0;  // coloured points (visible or not) more than 8 grey levels off
  size_t missed = 0;        // visible but not coloured
};

// `truth` holds the scene's colour at each point; `world` each point's world position.
Scored score(const PointCloud& cloud, const std::vector<PointCloud::Rgb>& truth, const std::vector<Vec3>& world,
             const synthetic::Scene& scene, const Rig& rig) {
  Scored s;
  const test::Visibility visibility(scene, rig);
  for (size_t i = 0; i < cloud.size(); ++i) {
    const bool visible = visibility.any_camera_sees(world[i]);
    const bool coloured = cloud.flags[i] & cloud_flags::kColoured;
    const bool close = std::abs(test::luma(cloud.rgb[i]) - test::luma(truth[i])) <= 8;
    if (visible) ++s.visible;
    if (visible && coloured && close) ++s.right;
    if (coloured && !close) ++s.wrong_colour;
    if (visible && !coloured) ++s.missed;
  }
  std::cout << "visible " << s.visible << ", right " << s.right << ", visible but uncoloured " << s.missed
            << ", coloured more than 8 grey levels off " << s.wrong_colour << "\n";
  return s;
}

// The still robot's images of the plain room, rendered once for all tests.
const std::vector<cv::Mat>& plain_room_images(const Rig& rig) {
  static const std::vector<cv::Mat> images = test::render_images(test::textured_room(), rig);
  return images;
}

struct StillScan {
  synthetic::Scene scene = test::textured_room();
  Pose T_world_body = make_pose(Vec3(0.4, -0.3, 0.55), 0.3, 0, 0);
  std::shared_ptr<Rig> rig = test::rig_in_world(T_world_body);
  PointCloud cloud;
  std::vector<PointCloud::Rgb> truth;
  std::vector<Vec3> world;

  explicit StillScan(const synthetic::Scene& s) : scene(s) { scan(); }
  StillScan() { scan(); }
  void scan() {
    synthetic::LidarScanOptions options;
    options.keep_colour = true;
    cloud = synthetic::scan_vlp16(scene, T_world_body * test::T_body_lidar(), "lidar", kStamp, options);
    truth = cloud.rgb;
    cloud.rgb.clear();
    for (const auto& p : cloud.points) world.push_back(T_world_body * test::T_body_lidar() * p.cast<double>());
  }
};

TEST(Colour, TexturedRoomTakesTheTextureNearestCentre) {
  StillScan s;
  ASSERT_GT(s.cloud.size(), 20000u);
  CloudColourer colourer(s.rig);
  CameraImages images{plain_room_images(*s.rig), {}};
  const auto stats = colourer.colour(s.cloud, images, ColourOptions{});
  const auto sc = score(s.cloud, s.truth, s.world, s.scene, *s.rig);
  RecordProperty("visible", std::to_string(sc.visible));
  EXPECT_GT(sc.visible, 5000u);
  EXPECT_GE(sc.right, 0.99 * sc.visible) << sc.right << " of " << sc.visible;
  EXPECT_EQ(stats.points, s.cloud.size());
  EXPECT_EQ(stats.coloured + stats.occluded + stats.unseen + stats.self_filtered, stats.points);
  EXPECT_GE(stats.coloured, sc.right);
  // Unseen points are flagged, keep no camera, and are not painted.
  size_t unflagged = 0;
  for (size_t i = 0; i < s.cloud.size(); ++i) {
    const bool coloured = s.cloud.flags[i] & cloud_flags::kColoured;
    if (coloured != (s.cloud.camera[i] != kNoCamera)) ++unflagged;
    if (!coloured && s.cloud.rgb[i] != (PointCloud::Rgb{0, 0, 0})) ++unflagged;
  }
  EXPECT_EQ(unflagged, 0u);
}

TEST(Colour, FeatheredBlendAndGreyCameras) {
  StillScan s;
  CloudColourer colourer(s.rig);
  ColourOptions blend;
  blend.fusion = Fusion::kBlend;
  PointCloud cloud = s.cloud;
  colourer.colour(cloud, CameraImages{plain_room_images(*s.rig), {}}, blend);
  auto sc = score(cloud, s.truth, s.world, s.scene, *s.rig);
  EXPECT_GE(sc.right, 0.99 * sc.visible) << sc.right << " of " << sc.visible;

  cloud = s.cloud;
  colourer.colour(cloud, CameraImages{test::render_images(s.scene, *s.rig, /*grey=*/true), {}}, ColourOptions{});
  sc = score(cloud, s.truth, s.world, s.scene, *s.rig);
  EXPECT_GE(sc.right, 0.99 * sc.visible) << sc.right << " of " << sc.visible;
  for (size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_TRUE(cloud.rgb[i][0] == cloud.rgb[i][1] && cloud.rgb[i][1] == cloud.rgb[i][2]) << i;
  }
}

TEST(Colour, OccluderDoesNotPaintWhatItHides) {
  // A plain red post in front of the robot: from the lidar's place (higher, farther back)
  // it hides other parts of the room than from the front cameras', so the lidar measures
  // wall and floor points the cameras see only the post at.
  synthetic::Scene scene = test::textured_room();
  synthetic::Material red;
  red.texture_contrast = 0;
  red.base = Vec3(30, 30, 230);  // BGR
  scene.add(synthetic::Box{Vec3(1.7, -0.2, 0), Vec3(1.9, 0.1, 2.5)}, red);
  StillScan s(scene);
  CloudColourer colourer(s.rig);
  CameraImages images{test::render_images(s.scene, *s.rig), {}};

  auto is_red = [](const PointCloud::Rgb& c) { return c[0] > 150 && c[1] < 90 && c[2] < 90; };
  auto count_false_red = [&](const PointCloud& cloud) {
    size_t n = 0;
    for (size_t i = 0; i < cloud.size(); ++i) {
      n += is_red(cloud.rgb[i]) && !is_red(s.truth[i]);
    }
    return n;
  };
  PointCloud with = s.cloud;
  const auto stats = colourer.colour(with, images, ColourOptions{});
  ColourOptions no_occlusion;
  no_occlusion.occlusion = false;
  PointCloud without = s.cloud;
  colourer.colour(without, images, no_occlusion);
  const size_t false_red_with = count_false_red(with), false_red_without = count_false_red(without);
  std::cout << "points painted the post's red that are not on it: occlusion on " << false_red_with << ", off "
            << false_red_without << "; flagged occluded " << stats.occluded << "\n";
  // What remains are points behind the post's lower part, which the lidar (its lowest ray
  // 15 deg down) never sampled: a surface the cloud lacks cannot hide anything.
  EXPECT_GT(false_red_without, 100u);
  EXPECT_LE(false_red_with, false_red_without / 4);
  EXPECT_GT(stats.occluded, 0u);
  const auto sc = score(with, s.truth, s.world, s.scene, *s.rig);
  EXPECT_GE(sc.right, 0.99 * sc.visible) << sc.right << " of " << sc.visible;
}

TEST(Colour, WalkingRobotNeedsTimeSync) {
  // Walking forward at 1 m/s: the lidar sweeps over 0.1 s from the cloud's stamp, and the
  // cameras take their images 0.15 s after it.
  const synthetic::Scene scene = test::textured_room();
  const Pose start = make_pose(Vec3(-0.5, 0.2, 0.55), 0.2, 0, 0);
  auto T_world_body = [&](double t) {
    Pose T = start;
    T.translation() += start.linear() * Vec3(1.0 * t, 0, 0);
    return T;
  };
  Trajectory odometry;
  for (int k = -10; k <= 40; ++k) odometry.add(kStamp + std::chrono::milliseconds(10 * k), T_world_body(0.01 * k));
  const double camera_delay = 0.15;
  const auto rig = test::rig_in_world(T_world_body(camera_delay));
  synthetic::LidarScanOptions options;
  options.keep_colour = true;
  PointCloud cloud = synthetic::scan_vlp16(
      scene, [&](double t) { return T_world_body(t) * test::T_body_lidar(); }, "lidar", kStamp, options);
  const auto truth = cloud.rgb;
  cloud.rgb.clear();
  std::vector<Vec3> world;
  for (size_t i = 0; i < cloud.size(); ++i) {
    world.push_back(T_world_body(cloud.time[i]) * test::T_body_lidar() * cloud.points[i].cast<double>());
  }
  const auto camera_time = kStamp + std::chrono::milliseconds(150);
  CameraImages images{test::render_images(scene, *rig), std::vector<Clock::time_point>(rig->cameras().size(), camera_time)};
  CloudColourer colourer(rig);

  PointCloud synced = cloud;
  colourer.colour(synced, images, ColourOptions{}, &odometry);
  const auto with = score(synced, truth, world, scene, *rig);
  ColourOptions no_sync;
  no_sync.time_sync = false;
  PointCloud unsynced = cloud;
  colourer.colour(unsynced, images, no_sync, &odometry);
  const auto without = score(unsynced, truth, world, scene, *rig);
  std::cout << "walking at 1 m/s: right " << with.right << " of " << with.visible << " with time sync, " << without.right
            << " without\n";
  EXPECT_GE(with.right, 0.99 * with.visible);
  EXPECT_LT(without.right, 0.9 * without.visible);
}

TEST(Colour, SelfFilterDropsTheLegs) {
  const auto model = robot::load_urdf_file(std::string(OMNIVIEW_SOURCE_DIR) + "/config/robots/spot/spot_like.urdf");
  std::vector<double> q = model.zero_positions();
  model.apply({{"fl.hy", 0.7}, {"fl.kn", -1.4}, {"fr.hy", 0.9}, {"fr.kn", -1.6}, {"hl.hy", 0.6}, {"hl.kn", -1.2}}, q);
  // Points on the legs' surfaces (their mesh vertices, in the body frame, seen from the
  // lidar) plus the room; the legs' points must all go, the room's (but what touches a
  // foot) must stay.
  StillScan s;
  PointCloud cloud = s.cloud;
  const Pose T_lidar_body = test::T_body_lidar().inverse();
  const auto poses = model.link_poses(q);
  size_t leg_points = 0;
  for (const auto& visual : model.visuals()) {
    const std::string& link = model.links()[visual.link].name;
    if (link.find("leg") == std::string::npos) continue;
    for (size_t k = 0; k < visual.mesh.positions.size(); k += 3) {
      cloud.points.push_back((T_lidar_body * poses[visual.link] * visual.mesh.positions[k].cast<double>()).cast<float>());
      ++leg_points;
    }
  }
  cloud.ring.resize(cloud.size(), 0);
  cloud.time.resize(cloud.size(), 0.f);
  const size_t room_points = s.cloud.size();
  ASSERT_GT(leg_points, 50u);
  SelfFilter filter(model, 0.03);
  const size_t marked = filter.mark(cloud, q, test::T_body_lidar());
  size_t legs_marked = 0;
  for (size_t i = room_points; i < cloud.size(); ++i) legs_marked += (cloud.flags[i] & cloud_flags::kSelf) != 0;
  EXPECT_EQ(legs_marked, leg_points);
  EXPECT_LE(marked - legs_marked, room_points / 100);
  CloudColourer colourer(s.rig);
  const auto stats = colourer.colour(cloud, CameraImages{plain_room_images(*s.rig), {}}, ColourOptions{});
  EXPECT_EQ(stats.self_filtered, marked);
  for (size_t i = room_points; i < cloud.size(); ++i) EXPECT_FALSE(cloud.flags[i] & cloud_flags::kColoured);
}

TEST(Colour, EmptyAndNonFinitePoints) {
  StillScan s;
  CloudColourer colourer(s.rig);
  const CameraImages images{plain_room_images(*s.rig), {}};
  PointCloud empty;
  empty.frame = "lidar";
  EXPECT_EQ(colourer.colour(empty, images, ColourOptions{}).points, 0u);
  PointCloud odd;
  odd.frame = "lidar";
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  odd.points = {{nan, 0, 0}, {inf, 1, 0}, {1e30f, -1e30f, 1e30f}, {0, 0, 0}, {2, 0, 0}};
  odd.time = {nan, 0, inf, -1e30f, 0};
  Trajectory still;
  still.add(odd.stamp, Pose::Identity());
  still.add(odd.stamp + std::chrono::seconds(1), Pose::Identity());
  const auto stats = colourer.colour(odd, images, ColourOptions{}, &still);
  EXPECT_EQ(stats.coloured + stats.unseen + stats.occluded, 5u);
  EXPECT_FALSE(odd.flags[0] & cloud_flags::kColoured);
  EXPECT_FALSE(odd.flags[1] & cloud_flags::kColoured);
}

TEST(Colour, ClearErrors) {
  StillScan s;
  CloudColourer colourer(s.rig);
  auto images = plain_room_images(*s.rig);
  PointCloud cloud = s.cloud;
  cloud.frame = "velodyne";
  try {
    colourer.colour(cloud, CameraImages{images, {}}, ColourOptions{});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'velodyne' is not connected to the rig's frame 'body'"), std::string::npos);
  }
  cloud.frame = "lidar";
  images[2] = cv::Mat(10, 10, CV_8UC3);
  try {
    colourer.colour(cloud, CameraImages{images, {}}, ColourOptions{});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("camera 'left' image is 10x10"), std::string::npos);
  }
  images.pop_back();
  EXPECT_THROW(colourer.colour(cloud, CameraImages{images, {}}, ColourOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace omniview
