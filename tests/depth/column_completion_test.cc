// Columns that complete measured geometry (core/depth/column_completion.h): the ground
// found, a lidar's top ring told, objects' sides carried down to the floor and a little past
// the top ring, and a view's surface taking them only where nothing was measured.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "cloud_scene.h"
#include "core/depth/column_completion.h"
#include "core/depth/measured_depth_view.h"

namespace omniview {
namespace {

constexpr float kGround = -0.5f;

// A VLP-16 at `origin` (level) scanning: the floor at kGround and a vertical wall x = wall_x
// from the floor up to wall_top; each ring every 0.5 deg of azimuth over +-40 deg.
struct Scan {
  std::vector<Eigen::Vector3f> in_sensor;  // as the sensor reports them
  std::vector<Eigen::Vector3f> in_robot;
};
Scan scan(const Eigen::Vector3f& origin, float wall_x, float wall_top) {
  Scan s;
  for (int ring = 0; ring < 16; ++ring) {
    const float el = (-15.f + 2.f * ring) * float(M_PI / 180);
    for (float az = -40; az <= 40; az += 0.5f) {
      const float a = az * float(M_PI / 180);
      const Eigen::Vector3f dir(std::cos(el) * std::cos(a), std::cos(el) * std::sin(a), std::sin(el));
      float t = (wall_x - origin.x()) / dir.x();  // the wall
      Eigen::Vector3f p = origin + t * dir;
      if (p.z() < kGround || p.z() > wall_top) {
        if (dir.z() >= 0) continue;  // over the wall: nothing (open sky)
        t = (kGround - origin.z()) / dir.z();  // the floor before the wall
        p = origin + t * dir;
        if (p.x() > wall_x) continue;
      }
      s.in_robot.push_back(p);
      s.in_sensor.push_back(p - origin);
    }
  }
  return s;
}

TEST(ColumnCompletion, TheGroundIsTheFullestSliceBelowTheSensors) {
  const Scan s = scan({0, 0, 0.3f}, 3.f, 2.f);
  const auto ground = estimate_ground_z(s.in_robot, 0.3f);
  ASSERT_TRUE(ground.has_value());
  EXPECT_NEAR(*ground, kGround, 0.02);
  // A wall alone spreads over every slice: no ground.
  const Scan high = scan({0, 0, 0.3f}, 1.f, 5.f);
  std::vector<Eigen::Vector3f> wall;
  std::copy_if(high.in_robot.begin(), high.in_robot.end(), std::back_inserter(wall),
               [](const Eigen::Vector3f& p) { return p.x() > 0.99f; });
  EXPECT_FALSE(estimate_ground_z(wall, 1.f, 0.2f).has_value());
  EXPECT_FALSE(estimate_ground_z({}, 0.3f).has_value());
}

TEST(ColumnCompletion, TheTopOfTheFieldIsTheHighestRing) {
  const Scan s = scan({0, 0, 0.3f}, 3.f, 5.f);
  const std::vector<uint8_t> top = top_of_field(s.in_sensor);
  ASSERT_EQ(top.size(), s.in_sensor.size());
  size_t flagged = 0;
  for (size_t i = 0; i < top.size(); ++i) {
    const float el = std::atan2(s.in_sensor[i].z(), s.in_sensor[i].head<2>().norm()) * float(180 / M_PI);
    if (top[i]) {
      ++flagged;
      EXPECT_NEAR(el, 15.f, 0.1f);
    } else {
      EXPECT_LT(el, 14.f);
    }
  }
  EXPECT_GT(flagged, 100u);
  std::vector<Eigen::Vector3f> with_nan = s.in_sensor;
  with_nan.push_back(Eigen::Vector3f::Constant(NAN));
  EXPECT_EQ(top_of_field(with_nan).back(), 0);
}

// Per column of the wall, the added points' heights.
std::pair<float, float> added_heights(const std::vector<Eigen::Vector3f>& added) {
  float low = INFINITY, high = -INFINITY;
  for (const auto& p : added) low = std::min(low, p.z()), high = std::max(high, p.z());
  return {low, high};
}

TEST(ColumnCompletion, AWallCutByTheRingsGoesDownToTheFloorAndALittlePastTheTopRing) {
  const Eigen::Vector3f lidar(0, 0, 0.3f);
  // Taller than the top ring reaches (0.3 + 2 tan 15 = 0.84), at the middle of a row of 5 cm
  // cells (a wall on a cell border has half its cells without a top-ring point).
  const Scan s = scan(lidar, 2.025f, 5.f);
  ColumnStats stats;
  const auto added = column_points(s.in_robot, top_of_field(s.in_sensor), kGround, {}, &stats, lidar);
  ASSERT_FALSE(added.empty());
  EXPECT_GT(stats.columns, 20u);
  EXPECT_GE(stats.open_tops, stats.columns * 9 / 10);  // the wall's columns reach the top ring
  for (const auto& p : added) EXPECT_NEAR(p.x(), 2.025f, 1e-3);
  const auto [low, high] = added_heights(added);
  EXPECT_NEAR(low, kGround, 1e-3);
  // 8 deg past the top ring as the lidar sees it: straight ahead at 2 m, and no higher than
  // that at the scan's far end (40 deg aside, 2.6 m).
  std::vector<Eigen::Vector3f> ahead;
  std::copy_if(added.begin(), added.end(), std::back_inserter(ahead),
               [](const Eigen::Vector3f& p) { return std::abs(p.y()) < 0.05f; });
  const float past_top = 23.f * float(M_PI / 180);
  EXPECT_NEAR(added_heights(ahead).second, lidar.z() + 2.025f * std::tan(past_top), 0.06f);
  EXPECT_LT(high, lidar.z() + 2.025f / std::cos(40.f * float(M_PI / 180)) * std::tan(past_top) + 0.06f);
  // Not a lidar's (no sensor known, no top told): down to the floor only.
  const auto down_only = column_points(s.in_robot, {}, kGround);
  const auto [low2, high2] = added_heights(down_only);
  EXPECT_NEAR(low2, kGround, 1e-3);
  EXPECT_LT(high2, lidar.z() + 2.025f * std::tan(15.f * float(M_PI / 180)));  // below the top ring
  // A storey at most.
  ColumnOptions low_ceiling;
  low_ceiling.max_height_m = 1.f;
  const auto capped = column_points(s.in_robot, top_of_field(s.in_sensor), kGround, low_ceiling, nullptr, lidar);
  EXPECT_LE(added_heights(capped).second, kGround + 1.f + 1e-3f);
}

TEST(ColumnCompletion, AnObjectTheTopRingPassesOverHasNoOpenTopAndTheFloorNoColumn) {
  const Eigen::Vector3f lidar(0, 0, 0.3f);
  // A low wall 6 m out, the floor before it: the rings from -1 deg up see the sky.
  const Scan s = scan(lidar, 6.f, 0.2f);
  ASSERT_TRUE(std::any_of(s.in_robot.begin(), s.in_robot.end(), [](const Eigen::Vector3f& p) { return p.x() < 5.f; }));
  ColumnStats stats;
  const auto added = column_points(s.in_robot, top_of_field(s.in_sensor), kGround, {}, &stats, lidar);
  EXPECT_GT(stats.columns, 20u);
  EXPECT_EQ(stats.open_tops, 0u);
  // The floor before it makes none (columns stand at their points, joined tops at cell centres).
  for (size_t i = 0; i < added.size(); ++i) EXPECT_NEAR(added[i].x(), 6.f, i < stats.added - stats.top_points ? 1e-3 : 0.026);
  EXPECT_LT(added_heights(added).second, 0.2f);
  // Non-finite and absurdly far points are skipped.
  const std::vector<Eigen::Vector3f> bad = {Eigen::Vector3f::Constant(NAN), Eigen::Vector3f(1, 0, INFINITY),
                                            Eigen::Vector3f(1e30f, 0, 1), Eigen::Vector3f(1, 1, -1e30f)};
  EXPECT_TRUE(column_points(bad, {1, 1, 1, 1}, kGround).empty());
  EXPECT_FALSE(estimate_ground_z(bad, 0.3f).has_value());
}

// A ceiling (or a canopy, a sign) has nothing under it down to the floor: points whose cell
// holds nothing lower than lowest_base_z make no column, and the added points are capped.
TEST(ColumnCompletion, OverheadPointsMakeNoColumnAndTheColumnsAreCapped) {
  std::vector<Eigen::Vector3f> points;
  for (float x = 1; x < 3; x += 0.05f) points.emplace_back(x, 0.f, 2.2f);  // a ceiling strip
  points.emplace_back(4.f, 0.f, 0.3f);                                     // a post's point
  ColumnOptions options;
  options.lowest_base_z = 0.8f;
  ColumnStats stats;
  const auto added = column_points(points, {}, kGround, options, &stats);
  EXPECT_EQ(stats.overhead, stats.columns - 1);
  ASSERT_FALSE(added.empty());
  for (const auto& p : added) EXPECT_NEAR(p.x(), 4.f, 1e-5);  // the post's column alone
  // complete_columns puts the bound 0.5 m above the highest camera or lidar.
  const auto rig = test::rig_in_world(Pose::Identity());
  std::vector<Eigen::Vector3f> with_floor = points;
  for (float x = -3; x < 3; x += 0.02f) with_floor.emplace_back(x, 1.f, kGround);
  const Completion completion = complete_columns(*rig, with_floor, {}, std::nullopt);
  ASSERT_TRUE(completion.ground_z.has_value());
  EXPECT_EQ(completion.stats.overhead, stats.overhead);
  // At most max_points added.
  options.max_points = 5;
  EXPECT_LE(column_points(points, {}, kGround, options).size(), 5u + 20u);  // the column under way ends
}

TEST(ColumnCompletion, OnlyALidarFrameOnTheRobotTellsItsTopRing) {
  const auto rig = test::rig_in_world(Pose::Identity());
  const auto lidar = lidar_origin(*rig, "lidar");
  ASSERT_TRUE(lidar.has_value());
  EXPECT_TRUE(lidar->isApprox(rig->frames().lookup(rig->default_frame(), "lidar").translation().cast<float>()));
  EXPECT_FALSE(lidar_origin(*rig, rig->default_frame()).has_value());
  EXPECT_FALSE(lidar_origin(*rig, rig->cameras().front().name).has_value());  // a depth camera's points
  EXPECT_FALSE(lidar_origin(*rig, "no such frame").has_value());
  auto far = test::rig_in_world(make_pose(Vec3(20, 0, 0), 0, 0, 0));
  EXPECT_FALSE(lidar_origin(*far, "world").has_value());  // a world frame, not a sensor
}

// A view's surface takes the columns only where the measured points left it empty: a wall's
// foot behind a sparsely measured near object must not break the object between its rings.
TEST(ColumnCompletion, TheViewTakesColumnsOnlyWhereNothingWasMeasured) {
  ViewSpec spec;
  spec.name = "p";
  spec.type = ViewType::kPerspective;
  spec.width = 200;
  spec.height = 100;
  spec.hfov_deg = 90;
  spec.distance = 5;
  spec.depth = Depth::kMeasured;
  const DepthSurface surface(spec);
  // Near: rings of a wall at 1 m, 2 deg apart (the view frame is the lidar's).
  const Scan near = scan({0, 0, 0}, 1.f, 10.f);
  std::vector<Eigen::Vector3f> measured;
  std::copy_if(near.in_robot.begin(), near.in_robot.end(), std::back_inserter(measured),
               [](const Eigen::Vector3f& p) { return p.x() < 1.01f; });
  // Far: a dense column field at 4 m behind it, and over the whole view.
  std::vector<Eigen::Vector3f> far;
  for (float y = -4; y <= 4; y += 0.02f) {
    for (float z = -4; z <= 4; z += 0.02f) far.emplace_back(4.f, y, z);
  }
  DepthStats stats;
  const auto view = surface.update(measured, Pose::Identity(), &stats, &far);
  EXPECT_GT(stats.completed_pixels, 0u);
  int near_pixels = 0, far_pixels = 0;
  for (int v = 0; v < spec.height; ++v) {
    for (int u = 0; u < spec.width; ++u) {
      Vec3 dir;
      ASSERT_TRUE(view->pixel_to_direction(u, v, dir));
      const double el = std::asin(dir.z() / dir.norm()) * 180 / M_PI;
      const float range = view->range_at(u, v);
      if (std::abs(std::atan2(dir.y(), dir.x())) > 38 * M_PI / 180) continue;  // past the scan's +-40 deg
      if (std::abs(el) < 14) {  // between the near wall's rings: the near wall
        EXPECT_NEAR(range * dir.x() / dir.norm(), 1.0, 0.02) << u << "," << v;
        ++near_pixels;
      } else if (std::abs(el) > 17) {  // past its rings: the columns
        EXPECT_NEAR(range * dir.x() / dir.norm(), 4.0, 0.05) << u << "," << v;
        ++far_pixels;
      }
    }
  }
  EXPECT_GT(near_pixels, 1000);
  EXPECT_GT(far_pixels, 1000);
  // Wherever the measured points alone made a surface, the columns leave it as it was.
  const auto alone = surface.update(measured, Pose::Identity());
  int compared = 0;
  for (int v = 0; v < spec.height; ++v) {
    for (int u = 0; u < spec.width; ++u) {
      if (alone->measured_at(u, v) < 255) continue;
      EXPECT_EQ(view->range_at(u, v), alone->range_at(u, v)) << u << "," << v;
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
}

// A VLP-16 at `origin` scanning a box [lo, hi] over the floor at kGround (0.2 deg steps
// over +-40 deg; floor returns within 8 m, nothing from the sky).
std::vector<Eigen::Vector3f> scan_box(const Eigen::Vector3f& origin, const Eigen::Vector3f& lo,
                                      const Eigen::Vector3f& hi) {
  std::vector<Eigen::Vector3f> points;
  for (int ring = 0; ring < 16; ++ring) {
    const float el = (-15.f + 2.f * ring) * float(M_PI / 180);
    for (float az = -40; az <= 40; az += 0.2f) {
      const float a = az * float(M_PI / 180);
      const Eigen::Vector3f dir(std::cos(el) * std::cos(a), std::cos(el) * std::sin(a), std::sin(el));
      float t0 = 0.f, t1 = INFINITY;  // the ray inside the box's slabs
      for (int k = 0; k < 3; ++k) {
        const float ta = (lo[k] - origin[k]) / dir[k], tb = (hi[k] - origin[k]) / dir[k];
        t0 = std::max(t0, std::min(ta, tb)), t1 = std::min(t1, std::max(ta, tb));
      }
      if (t0 <= t1) {
        points.push_back(origin + t0 * dir);
      } else if (dir.z() < 0) {
        const Eigen::Vector3f floor = origin + (kGround - origin.z()) / dir.z() * dir;
        if (floor.head<2>().norm() < 8.f) points.push_back(floor);
      }
    }
  }
  return points;
}

// A crate 0.3 m below a VLP-16 (its top at z = 0, x 1.4 .. 2.0 m ahead, 0.8 m wide) on the
// floor at kGround: two rings cross its top 0.35 m apart and the face's top ring lies
// 2 cm under its edge; nothing between them.
std::vector<Eigen::Vector3f> scan_crate(const Eigen::Vector3f& origin) {
  return scan_box(origin, {1.4f, -0.4f, kGround}, {2.0f, 0.4f, 0.f});
}

std::vector<Eigen::Vector3f> in_sensor(std::vector<Eigen::Vector3f> points, const Eigen::Vector3f& origin) {
  for (auto& p : points) p -= origin;
  return points;
}

// A table's top (legs left out) 0.3 m above a VLP-16 and 0.8 m over the floor: the upper
// rings see its underside, the lower ones the floor under and past it. The columns from
// the underside stop above where those rays passed (the highest returning ring under it,
// -5 deg, passes 0.15-0.2 m below the lidar there; the rings between saw the sky, no
// return, no ray); a crate standing on the floor, whose foot no ray passes under, keeps
// its columns down to the floor.
TEST(ColumnCompletion, AColumnEndsAboveWhereTheLidarSawUnderIt) {
  const Eigen::Vector3f lidar(0, 0, 0);
  const std::vector<Eigen::Vector3f> table = scan_box(lidar, {1.2f, -0.5f, 0.3f}, {2.2f, 0.5f, 0.34f});
  const auto under_the_table = [](const std::vector<Eigen::Vector3f>& added) {
    return std::count_if(added.begin(), added.end(), [](const Eigen::Vector3f& p) {
      return p.x() > 1.25f && p.x() < 2.15f && std::abs(p.y()) < 0.45f && p.z() < -0.15f;
    });
  };
  ColumnStats stats;
  const auto unseen = column_points(table, top_of_field(in_sensor(table, lidar)), kGround, {}, &stats, lidar);
  EXPECT_EQ(stats.seen_under, 0u);
  EXPECT_GT(under_the_table(unseen), 200) << "the columns filled the space under the table";
  const auto seen = column_points(table, lidar_flags(in_sensor(table, lidar)), kGround, {}, &stats, lidar);
  EXPECT_GT(stats.seen_under, 20u);
  EXPECT_EQ(under_the_table(seen), 0);
  // The underside itself stays (a column's top point is its lowest measured one).
  EXPECT_GT(std::count_if(seen.begin(), seen.end(), [](const Eigen::Vector3f& p) { return std::abs(p.z() - 0.3f) < 0.01f; }),
            20);

  const Eigen::Vector3f high(0, 0, 0.3f);
  const std::vector<Eigen::Vector3f> crate = scan_crate(high);
  const auto plain = column_points(crate, top_of_field(in_sensor(crate, high)), kGround, {}, nullptr, high);
  const auto judged = column_points(crate, lidar_flags(in_sensor(crate, high)), kGround, {}, &stats, high);
  EXPECT_EQ(stats.seen_under, 0u);
  EXPECT_EQ(plain.size(), judged.size());
}

// Rays judge free space only where they pass within the radius of the line, end past it,
// and cross it between the floor and the object's lowest point; the second highest of two
// counts (one stray return lowers nothing by itself).
TEST(SensorRays, TheHighestCrossingOfRaysThatPassUnder) {
  const Eigen::Vector3f sensor(0, 0, 1);
  // Rays along +x ending on the floor at z = 0 past x = 2, and one stray ending at (4, 0, 0.9).
  std::vector<Eigen::Vector3f> ends = {{4, 0, 0}, {8, 0, 0}, {3, 0, 0}, {4, 0, 0.9f}, {8, 0.5f, 0}};
  std::vector<uint8_t> flags(ends.size(), SensorRays::kSeenFrom);
  flags[2] = kTopOfField;  // not a ray of this sensor
  const SensorRays rays(ends, flags, sensor);
  // At x = 2 the rays to (4,0,0) and (8,0,0) pass at 0.5 and 0.75; the stray at 0.95.
  const auto h = rays.highest_crossing({2, 0}, 0.97f, 0.f, 0.01f);
  ASSERT_TRUE(h.has_value());
  EXPECT_NEAR(*h, 0.75f, 1e-4f);
  EXPECT_FALSE(rays.highest_crossing({2, 0}, 0.97f, 0.f, 0.01f, 4).has_value());
  // Below the object's lowest point only: with it at 0.6, the one ray at 0.5 is too few.
  EXPECT_FALSE(rays.highest_crossing({2, 0}, 0.6f, 0.f, 0.01f).has_value());
  EXPECT_TRUE(rays.highest_crossing({2, 0}, 0.6f, 0.f, 0.01f, 1).has_value());
  // Off the rays' line, past their ends, or with no ray: nothing known.
  EXPECT_FALSE(rays.highest_crossing({2, 0.05f}, 0.97f, 0.f, 0.01f, 1).has_value());
  EXPECT_FALSE(rays.highest_crossing({9, 0}, 0.97f, 0.f, 0.01f, 1).has_value());
  EXPECT_FALSE(SensorRays(ends, std::vector<uint8_t>(ends.size(), 0), sensor).highest_crossing({2, 0}, 0.97f, 0.f, 0.01f, 1));
}

TEST(FlatTops, ACratesTopIsJoinedBetweenTheRingsThatCrossIt) {
  const Eigen::Vector3f lidar(0, 0, 0.3f);
  const std::vector<Eigen::Vector3f> points = scan_crate(lidar);
  const auto top_cells = [](const std::vector<Eigen::Vector3f>& pts) {
    std::set<std::pair<int, int>> cells;
    for (const auto& p : pts) {
      if (std::abs(p.z()) < 0.03f && p.x() > 1.4f && p.x() < 2.0f && std::abs(p.y()) < 0.4f) {
        cells.emplace(int(std::floor(p.x() / 0.05f)), int(std::floor(p.y() / 0.05f)));
      }
    }
    return cells;
  };
  ColumnOptions unjoined;
  unjoined.tops.max_gap_m = 0;
  ColumnStats stats;
  const auto without = column_points(points, {}, kGround, unjoined, &stats, lidar);
  EXPECT_EQ(stats.top_points, 0u);
  const auto with = column_points(points, {}, kGround, {}, &stats, lidar);
  EXPECT_GT(stats.top_points, 50u);
  std::vector<Eigen::Vector3f> all_without = points, all_with = points;
  all_without.insert(all_without.end(), without.begin(), without.end());
  all_with.insert(all_with.end(), with.begin(), with.end());
  // The top is 12 x 16 cells; the rings and the face's edge hold a third of them, and
  // the joins all but the strip behind the last ring (past it the rings saw the floor).
  const size_t cells = 12 * 16;
  EXPECT_LT(top_cells(all_without).size(), cells / 2) << top_cells(all_without).size();
  EXPECT_GE(top_cells(all_with).size(), cells * 2 / 3) << top_cells(all_with).size();
  // Every joined point lies on the top, none past its far edge (the rings there hit the floor).
  for (size_t i = with.size() - stats.top_points; i < with.size(); ++i) {
    EXPECT_NEAR(with[i].z(), 0.f, 0.03f);
    EXPECT_GT(with[i].x(), 1.35f);
    EXPECT_LT(with[i].x(), 2.0f);
  }
}

TEST(FlatTops, TopsAreJoinedOnlyOverEmptyCellsCloseByAndAtOneHeight) {
  const std::vector<CellTop> tops = {{0, 0, 0.f}, {8, 0, 0.02f}};
  // Seven empty cells between two tops 0.4 m apart: joined, the heights interpolated.
  std::vector<Eigen::Vector3f> joined = flat_top_points({}, tops, Eigen::Vector2f::Zero());
  ASSERT_EQ(joined.size(), 7u);
  for (const auto& p : joined) {
    EXPECT_GT(p.x(), 0.05f);
    EXPECT_LT(p.x(), 0.4f);
    EXPECT_NEAR(p.y(), 0.025f, 1e-5f);
    EXPECT_NEAR(p.z(), 0.02f * (p.x() - 0.025f) / 0.4f, 1e-4f);
  }
  // A floor point between them: the lidar saw the floor there, not a top.
  EXPECT_TRUE(flat_top_points({Eigen::Vector3f(0.22f, 0.02f, -0.5f)}, tops, Eigen::Vector2f::Zero()).empty());
  // Two heights 10 cm apart, or 0.6 m apart: not one top.
  EXPECT_TRUE(flat_top_points({}, {{0, 0, 0.f}, {8, 0, 0.1f}}, Eigen::Vector2f::Zero()).empty());
  EXPECT_TRUE(flat_top_points({}, {{0, 0, 0.f}, {12, 0, 0.f}}, Eigen::Vector2f::Zero()).empty());
  // Along a diagonal too; far from the sensor, not at all.
  EXPECT_EQ(flat_top_points({}, {{0, 0, 0.f}, {5, 5, 0.f}}, Eigen::Vector2f::Zero()).size(), 4u);
  EXPECT_TRUE(flat_top_points({}, tops, Eigen::Vector2f(100.f, 0.f)).empty());
  EXPECT_TRUE(flat_top_points({}, {}, Eigen::Vector2f::Zero()).empty());
}

}  // namespace
}  // namespace omniview
