// The geometry a depth view stands on (server/pipeline/depth/source_geometry.h): clouds of a
// moving robot accumulated where the world is, aged out by capture time, kept within the
// point budget, bad clouds counted and skipped. No daemon.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/map/worker_threads.h"
#include "core/synthetic/spot_like_rig.h"
#include "server/pipeline/depth/source_geometry.h"

namespace omniview {
namespace {

using namespace std::chrono_literals;
using Time = std::chrono::system_clock::time_point;

const Time kT0 = Time(std::chrono::seconds(1'700'000'000));

// A wall 3 m ahead of the world's origin (x = 3), 2 m wide and high, every 5 cm.
std::vector<Eigen::Vector3d> wall_in_world() {
  std::vector<Eigen::Vector3d> points;
  for (double y = -1; y <= 1; y += 0.05) {
    for (double z = 0; z <= 2; z += 0.05) points.emplace_back(3, y, z);
  }
  return points;
}

// What the robot's lidar measures of the wall from `T_world_body`, in the body frame.
PointCloud scan(const Pose& T_world_body, Time stamp, const std::string& frame) {
  PointCloud cloud;
  cloud.frame = frame;
  cloud.stamp = stamp;
  const Pose T_body_world = T_world_body.inverse();
  for (const auto& p : wall_in_world()) cloud.points.push_back((T_body_world * p).cast<float>());
  return cloud;
}

// The largest distance of a point from the wall once put back into the world at `T_world_body`.
double worst_off_the_wall(const std::vector<Eigen::Vector3f>& points, const Pose& T_world_body) {
  double worst = 0;
  for (const auto& p : points) worst = std::max(worst, std::abs((T_world_body * p.cast<double>()).x() - 3));
  return worst;
}

class Geometry : public ::testing::Test {
 protected:
  const Rig rig = synthetic::spot_like_rig();
  const std::string body = rig.default_frame();
  const std::chrono::steady_clock::time_point arrival = std::chrono::steady_clock::now();

  // A lidar's cloud delivered in the robot frame instead (no sensor known), as a geometry
  // alone makes it.
  GeometrySnapshot completed_in_robot_frame(PointCloud cloud, const Rig& with_lidar, const Pose& T_body_lidar) const {
    cloud.frame = body;
    for (auto& p : cloud.points) p = (T_body_lidar * p.cast<double>()).cast<float>();
    SourceGeometry unknown_sensor;
    unknown_sensor.add(cloud, with_lidar, nullptr, arrival);
    return *unknown_sensor.latest();
  }
};

TEST_F(Geometry, AMovingRobotsCloudsAreAccumulatedWhereTheWorldIs) {
  // The robot drives 0.5 m towards the wall and turns 10 deg between two rotations.
  const Pose T_world_body0 = make_pose(Vec3(0, 0, 0.5), 0, 0, 0);
  const Pose T_world_body1 = make_pose(Vec3(0.5, 0.1, 0.5), 10 * M_PI / 180, 0, 0);
  Trajectory odometry;
  odometry.add(kT0, T_world_body0);
  odometry.add(kT0 + 100ms, T_world_body1);

  SourceGeometry moving;
  moving.add(scan(T_world_body0, kT0, body), rig, &odometry, arrival);
  moving.add(scan(T_world_body1, kT0 + 100ms, body), rig, &odometry, arrival);
  const auto snapshot = moving.latest();
  ASSERT_TRUE(snapshot);
  EXPECT_EQ(snapshot->clouds, 2u);
  EXPECT_EQ(snapshot->points->size(), 2 * wall_in_world().size());
  EXPECT_EQ(snapshot->frame, body);
  EXPECT_EQ(snapshot->stamp, kT0 + 100ms);
  // Every point, the older rotation's too, is on the wall as seen from where the robot is now.
  EXPECT_LT(worst_off_the_wall(*snapshot->points, T_world_body1), 1e-4);

  // Without odometry the robot is taken to be still: the older rotation's wall stands
  // half a metre too far (what the accumulation with motion is for).
  SourceGeometry still;
  still.add(scan(T_world_body0, kT0, body), rig, nullptr, arrival);
  still.add(scan(T_world_body1, kT0 + 100ms, body), rig, nullptr, arrival);
  EXPECT_GT(worst_off_the_wall(*still.latest()->points, T_world_body1), 0.4);
}

TEST_F(Geometry, TheCamerasOccludersAreMadeOncePerGeometryAndShared) {
  apply_worker_threads_from_env();  // OMNIVIEW_THREADS=1 (the TSan stage): no TBB hand-offs to miss
  // Every depth view of the source judges occlusion against the same occluders: made at the
  // first view's update, handed to the next as they are, made again for new geometry only.
  const auto shared_rig = std::make_shared<const Rig>(rig);
  SourceGeometry geometry;
  const Pose here = make_pose(Vec3(0, 0, 0.5), 0, 0, 0);
  geometry.add(scan(here, kT0, body), rig, nullptr, arrival);
  const ViewOcclusionOptions options;
  const auto first = geometry.occluders(*geometry.latest(), shared_rig, options);
  ASSERT_EQ(first->cameras.size(), rig.cameras().size());
  EXPECT_EQ(geometry.occluders(*geometry.latest(), shared_rig, options), first);
  // The same as made for the points (and the columns completing them) directly.
  const auto latest = geometry.latest();
  const Occlusion direct =
      points_occlusion(*geometry.range_images(shared_rig, options.cell_deg), *latest->points, body, Pose::Identity(),
                       options, latest->completion ? &latest->completion->get().points : nullptr);
  for (size_t c = 0; c < direct.cameras.size(); ++c) EXPECT_EQ(direct.cameras[c].depth, first->cameras[c].depth);
  // The wall straight ahead hides what lies behind it from the front cameras.
  bool covers = false;
  for (float d : first->cameras[0].depth) covers = covers || (d > 0 && d < 5);
  EXPECT_TRUE(covers);
  geometry.add(scan(here, kT0 + 100ms, body), rig, nullptr, arrival);
  EXPECT_NE(geometry.occluders(*geometry.latest(), shared_rig, options), first);
}

TEST_F(Geometry, CloudsLeaveByCaptureTimeBehindTheNewest) {
  GeometryOptions options;
  options.keep = 500ms;
  SourceGeometry geometry(options);
  const Pose here = make_pose(Vec3(0, 0, 0.5), 0, 0, 0);
  for (auto t : {0ms, 300ms, 700ms}) geometry.add(scan(here, kT0 + t, body), rig, nullptr, arrival);
  EXPECT_EQ(geometry.latest()->clouds, 2u);  // the first is 700 ms behind the newest
  EXPECT_EQ(geometry.latest()->version, 3u);
  // A cloud that arrives late (an older stamp) is aged out against the newest one too.
  geometry.add(scan(here, kT0 + 100ms, body), rig, nullptr, arrival);
  EXPECT_EQ(geometry.latest()->clouds, 2u);
  EXPECT_EQ(geometry.latest()->stamp, kT0 + 700ms);
}

// A cloud that took seconds to reach the geometry (a starved machine: the accumulation
// alone took that long under a sanitizer in CI) is still the newest the source has: its
// freshness counts from when its snapshot was made, its age from the cloud's arrival.
TEST_F(Geometry, FreshnessCountsFromTheSnapshotNotFromTheCloudsArrival) {
  SourceGeometry geometry;
  const auto now = std::chrono::steady_clock::now();
  const auto long_ago = now - 3 * kFreshGeometry;
  geometry.add(scan(make_pose(Vec3(0, 0, 0.5), 0, 0, 0), kT0, body), rig, nullptr, long_ago);
  const auto snapshot = geometry.latest();
  ASSERT_TRUE(snapshot);
  EXPECT_EQ(snapshot->arrival, long_ago);
  EXPECT_GE(snapshot->ready, now);
  EXPECT_TRUE(fresh_geometry(snapshot->ready, std::chrono::steady_clock::now()));
  EXPECT_FALSE(fresh_geometry(snapshot->ready, snapshot->ready + kFreshGeometry));
}

TEST_F(Geometry, ThePointBudgetDropsTheOldestCloudsAndThinsOneTooBig) {
  GeometryOptions options;
  options.max_points = 2000;
  SourceGeometry geometry(options);
  const Pose here = make_pose(Vec3(0, 0, 0.5), 0, 0, 0);
  const size_t per_scan = wall_in_world().size();  // ~1,600
  geometry.add(scan(here, kT0, body), rig, nullptr, arrival);
  geometry.add(scan(here, kT0 + 100ms, body), rig, nullptr, arrival);
  EXPECT_EQ(geometry.latest()->clouds, 1u);
  EXPECT_EQ(geometry.latest()->points->size(), per_scan);

  options.max_points = 500;
  SourceGeometry small(options);
  small.add(scan(here, kT0, body), rig, nullptr, arrival);
  const size_t kept = small.latest()->points->size();
  EXPECT_LE(kept, 500u);
  EXPECT_GE(kept, 375u) << "an even subset (every 4th point here), not a corner of the cloud";
  EXPECT_LT(worst_off_the_wall(*small.latest()->points, here), 1e-4);
}

TEST_F(Geometry, BadCloudsAreCountedSkippedAndSaidWhy) {
  SourceGeometry geometry;
  const Pose here = make_pose(Vec3(0, 0, 0.5), 0, 0, 0);
  geometry.add(scan(here, kT0, "nowhere"), rig, nullptr, arrival);
  EXPECT_FALSE(geometry.latest());
  EXPECT_EQ(geometry.skipped(), 1u);
  EXPECT_NE(geometry.message().find("'nowhere'"), std::string::npos) << geometry.message();

  PointCloud no_returns = scan(here, kT0, body);
  for (auto& p : no_returns.points) p.x() = std::numeric_limits<float>::quiet_NaN();
  geometry.add(no_returns, rig, nullptr, arrival);
  EXPECT_EQ(geometry.skipped(), 2u);
  EXPECT_NE(geometry.message().find("no finite point"), std::string::npos) << geometry.message();

  // Some non-finite points in a good cloud: those alone are left out, and the message clears.
  PointCloud some = scan(here, kT0, body);
  some.points[0].y() = std::numeric_limits<float>::infinity();
  geometry.add(some, rig, nullptr, arrival);
  ASSERT_TRUE(geometry.latest());
  EXPECT_EQ(geometry.latest()->points->size(), wall_in_world().size() - 1);
  EXPECT_EQ(geometry.message(), "");
}

TEST_F(Geometry, ADepthCamerasPointsAreInItsOpticalFrame) {
  // Points 2 m along the frontleft camera's optical axis land where that camera looks.
  PointCloud depth;
  depth.frame = rig.cameras()[0].name;
  depth.stamp = kT0;
  depth.points.emplace_back(0, 0, 2);
  SourceGeometry geometry;
  geometry.add(depth, rig, nullptr, arrival);
  ASSERT_TRUE(geometry.latest());
  const Pose T_body_camera = rig.camera_pose(body, 0);
  const Eigen::Vector3d expected = T_body_camera * Eigen::Vector3d(0, 0, 2);
  EXPECT_LT((geometry.latest()->points->at(0).cast<double>() - expected).norm(), 1e-5);
}

// The geometry is completed by columns (core/depth/column_completion.h): a lidar's cloud in
// its own frame tells its top ring, so a wall it cut short goes on a little past it; the
// same points in the robot frame (no sensor known) are carried down to the floor only.
TEST_F(Geometry, ALidarsCloudIsCompletedByColumnsPastItsTopRing) {
  Rig with_lidar = rig;
  const Pose T_body_lidar = make_pose(Vec3(-0.1, 0, 0.3), 0, 0, 0);
  with_lidar.add_frame("lidar", body, T_body_lidar);
  // A VLP-16's rings (-15..+15 deg, every 2) over +-40 deg: the floor 0.8 m below the
  // lidar, a wall 3 m ahead of it.
  PointCloud cloud;
  cloud.frame = "lidar";
  cloud.stamp = kT0;
  for (int ring = 0; ring < 16; ++ring) {
    const double el = (-15.0 + 2 * ring) * M_PI / 180;
    for (double az = -40; az <= 40; az += 0.5) {
      const Vec3 dir(std::cos(el) * std::cos(az * M_PI / 180), std::cos(el) * std::sin(az * M_PI / 180), std::sin(el));
      const double to_wall = 3 / dir.x(), to_floor = dir.z() < 0 ? -0.8 / dir.z() : INFINITY;
      cloud.points.push_back((std::min(to_wall, to_floor) * dir).cast<float>());
    }
  }
  SourceGeometry geometry;
  geometry.add(cloud, with_lidar, nullptr, arrival);
  const auto snapshot = geometry.latest();
  ASSERT_TRUE(snapshot && snapshot->completion);
  const Completion& completion = snapshot->completion->get();
  ASSERT_TRUE(completion.ground_z.has_value());
  EXPECT_NEAR(*completion.ground_z, -0.5, 0.01);  // in the body frame
  EXPECT_GT(completion.stats.open_tops, 10u);
  float highest = -INFINITY;
  for (const auto& p : completion.points) highest = std::max(highest, p.z());
  const float top_ring = 0.3f + 3 * std::tan(15 * float(M_PI / 180));  // straight ahead
  EXPECT_GT(highest, top_ring + 0.2f);

  // The same points delivered in the robot frame: columns, but none past the top.
  const auto down_only_snapshot = completed_in_robot_frame(cloud, with_lidar, T_body_lidar);
  const Completion& down_only = down_only_snapshot.completion->get();
  EXPECT_GT(down_only.stats.columns, 10u);
  EXPECT_EQ(down_only.stats.open_tops, 0u);
}

// A table's top (legs left out) 0.1 m above the lidar: columns from its underside end
// above where the lower rings passed under it, judged by the newest rotation's rays only
// (an older one's started where the robot stood then: taken from here they would cut
// through what stands in the way).
TEST_F(Geometry, AColumnUnderATableEndsAboveWhereTheNewestRotationSawThrough) {
  Rig with_lidar = rig;
  const Pose T_body_lidar = make_pose(Vec3(-0.1, 0, 0.3), 0, 0, 0);
  with_lidar.add_frame("lidar", body, T_body_lidar);
  const auto table_scan = [&](std::chrono::system_clock::time_point stamp) {
    PointCloud cloud;
    cloud.frame = "lidar";
    cloud.stamp = stamp;
    const Eigen::Vector3d lo(1.2, -0.5, 0.1), hi(2.2, 0.5, 0.14);  // in the lidar's frame
    for (int ring = 0; ring < 16; ++ring) {
      const double el = (-15.0 + 2 * ring) * M_PI / 180;
      for (double az = -40; az <= 40; az += 0.2) {
        const Vec3 dir(std::cos(el) * std::cos(az * M_PI / 180), std::cos(el) * std::sin(az * M_PI / 180),
                       std::sin(el));
        double t0 = 0, t1 = INFINITY;
        for (int k = 0; k < 3; ++k) {
          const double ta = (lo[k]) / dir[k], tb = (hi[k]) / dir[k];
          t0 = std::max(t0, std::min(ta, tb)), t1 = std::min(t1, std::max(ta, tb));
        }
        const double to_floor = dir.z() < 0 ? -0.8 / dir.z() : INFINITY;
        const double t = t0 <= t1 ? t0 : to_floor;
        if (t < 8) cloud.points.push_back((t * dir).cast<float>());
      }
    }
    return cloud;
  };
  const auto under_the_table = [&](const Completion& c) {
    // In the body frame: the underside at 0.4 (under the rig's bound for overhead things,
    // column_completion.h), the floor at -0.5; the highest ring returning under it passes
    // about 0.13 up.
    return std::count_if(c.points.begin(), c.points.end(), [](const Eigen::Vector3f& p) {
      return p.x() > 1.2f && p.x() < 2.0f && std::abs(p.y()) < 0.45f && p.z() < 0.1f;
    });
  };
  SourceGeometry geometry;
  geometry.add(table_scan(kT0), with_lidar, nullptr, arrival);
  const auto once = geometry.latest();
  const Completion& seen = once->completion->get();
  EXPECT_GT(seen.stats.seen_under, 20u);
  EXPECT_EQ(under_the_table(seen), 0);

  // With a second rotation accumulated, the newest one's rays still judge.
  geometry.add(table_scan(kT0 + 100ms), with_lidar, nullptr, arrival);
  const auto twice = geometry.latest();
  const Completion& again = twice->completion->get();
  EXPECT_GT(again.stats.seen_under, 20u);
  EXPECT_EQ(under_the_table(again), 0);

  // The same points in the robot frame (no sensor known): no rays, the columns reach the floor.
  const auto blind = completed_in_robot_frame(table_scan(kT0), with_lidar, T_body_lidar);
  const Completion& filled = blind.completion->get();
  EXPECT_EQ(filled.stats.seen_under, 0u);
  EXPECT_GT(under_the_table(filled), 100);
}

}  // namespace
}  // namespace omniview
