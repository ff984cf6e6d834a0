// The ray caster itself: intersections, and scenes that really coincide with view surfaces
// (the premise of every golden test).
#include <gtest/gtest.h>

#include <cmath>

#include "core/synthetic/scene.h"
#include "core/view/view.h"
#include "tests/golden/golden.h"

namespace omniview {
namespace {

using synthetic::Box;
using synthetic::Cylinder;
using synthetic::Plane;
using synthetic::Scene;
using synthetic::Sphere;

TEST(SyntheticScene, BoxFromInsideAndOutside) {
  Scene room;
  room.add(Box{Vec3(-1, -2, 0), Vec3(3, 2, 2.5)});
  double t;
  Vec3 p;
  ASSERT_TRUE(room.intersect(Vec3(0, 0, 1), Vec3(1, 0, 0), t, p));  // inside: the far wall
  EXPECT_NEAR(t, 3, 1e-12);
  ASSERT_TRUE(room.intersect(Vec3(0, 0, 1), Vec3(0, 0, -2), t, p));  // dir need not be unit
  EXPECT_NEAR(p.z(), 0, 1e-12);
  const auto from_outside = room.intersect(Vec3(-5, 0, 1), Vec3(1, 0, 0));
  ASSERT_TRUE(from_outside);
  EXPECT_NEAR(from_outside->point.x(), -1, 1e-12);
  EXPECT_TRUE(from_outside->normal.isApprox(Vec3(-1, 0, 0)));  // faces the ray's origin
  EXPECT_FALSE(room.intersect(Vec3(-5, 0, 1), Vec3(-1, 0, 0)));  // looking away
  EXPECT_FALSE(room.intersect(Vec3(-5, 5, 1), Vec3(1, 0, 0)));   // passing beside it
}

TEST(SyntheticScene, BoundedPlaneCylinderAndNearestHit) {
  Scene s;
  s.add(Plane{Vec3::UnitX(), 2.0, Vec3(-10, -1, 0), Vec3(10, 1, 1)});  // a 2 x 1 m panel
  s.add(Sphere{Vec3::Zero(), 5.0});
  s.add(Cylinder{Vec3::Zero(), 3.0, 0.0, 1.0});
  const auto panel = s.intersect(Vec3(0, 0, 0.5), Vec3(1, 0, 0));
  ASSERT_TRUE(panel);
  EXPECT_EQ(panel->shape, 0u);
  const auto above_panel = s.intersect(Vec3(0, 0, 1.5), Vec3(1, 0, 0));  // misses panel and cylinder
  ASSERT_TRUE(above_panel);
  EXPECT_EQ(above_panel->shape, 1u);
  const auto beside = s.intersect(Vec3(0, 0, 0.5), Vec3(0, 1, 0));
  ASSERT_TRUE(beside);
  EXPECT_EQ(beside->shape, 2u);
  EXPECT_NEAR(beside->t, 3, 1e-12);
}

TEST(SyntheticScene, TextureVariesInEveryChannelAndDirection) {
  // Along a metre in any axis direction, every channel swings by tens of levels: a mirrored
  // or swapped axis cannot go unnoticed.
  const Vec3 start(0.3, -0.7, 1.1);
  for (int axis = 0; axis < 3; ++axis) {
    Vec3 lo = Vec3::Constant(255), hi = Vec3::Zero();
    for (int i = 0; i <= 100; ++i) {
      const Vec3 c = Scene::texture(start + 0.01 * i * Vec3::Unit(axis));
      lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
    }
    for (int c = 0; c < 3; ++c) EXPECT_GT(hi[c] - lo[c], 40) << "channel " << c << " along axis " << axis;
  }
}

TEST(SyntheticScene, MatchingSceneContainsEveryViewSurfacePoint) {
  const Pose T_world_frame = make_pose(Vec3(1, -2, 0.5), 0.4, 0, 0);  // frame yawed, not tilted
  for (ViewType type : {ViewType::kPerspective, ViewType::kBirdseye, ViewType::kCylindrical, ViewType::kMercator,
                        ViewType::kEquirectangular, ViewType::kFisheye}) {
    ViewSpec v = golden::view(type, 64, 48);
    v.position = Vec3(0.2, 0.1, 1.2);
    v.yaw_deg = 30;
    if (type == ViewType::kPerspective) v.pitch_deg = 15, v.roll_deg = 5;
    if (type == ViewType::kBirdseye) v.pitch_deg = 80, v.ground_z = -0.3;
    if (type == ViewType::kMercator) v.lat_min_deg = -80, v.lat_max_deg = 80;
    v.radius = 4;
    v.distance = 2.5;
    const Scene scene = Scene::matching(v, T_world_frame);
    const auto view = View::create(v);
    const Pose T_world_view = T_world_frame * v.T_frame_view();
    int checked = 0;
    for (int y = 0; y < v.height; y += 7) {
      for (int x = 0; x < v.width; x += 7) {
        Vec3 p;
        if (!view->pixel_to_point(x, y, p)) continue;
        const Vec3 expected = T_world_view * p;
        const auto hit = scene.intersect(T_world_view.translation(), expected - T_world_view.translation());
        ASSERT_TRUE(hit) << to_string(type) << " pixel " << x << "," << y;
        EXPECT_LT((hit->point - expected).norm(), 1e-6) << to_string(type) << " pixel " << x << "," << y;
        ++checked;
      }
    }
    EXPECT_GT(checked, 20) << to_string(type);
  }
  ViewSpec tilted = golden::view(ViewType::kCylindrical, 64, 48);
  tilted.pitch_deg = 10;
  EXPECT_THROW(Scene::matching(tilted), std::invalid_argument);
}

}  // namespace
}  // namespace omniview
