// The measured-depth surface piece by piece: splat, gap fill, fallback to the fixed
// surface, bad points; and occlusion in the map builder.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>

#include "core/depth/camera_occluders.h"
#include "core/depth/depth_image_points.h"
#include "core/depth/measured_depth_view.h"
#include "core/depth/range_splat.h"
#include "core/map/fusion_map.h"

namespace omniview {
namespace {

ViewSpec perspective(int w = 200, int h = 100) {
  ViewSpec s;
  s.name = "p";
  s.type = ViewType::kPerspective;
  s.width = w;
  s.height = h;
  s.hfov_deg = 90;
  s.distance = 5;
  s.depth = Depth::kMeasured;
  return s;
}

// A wall x = d in the view frame sampled like a lidar at the view's centre: rings every
// `ring_deg` of elevation within +-15 deg (a VLP-16's), a sample every 0.2 deg of azimuth.
std::vector<Eigen::Vector3f> wall_rings(double d, double ring_deg, double y_min = -10, double y_max = 10) {
  std::vector<Eigen::Vector3f> points;
  for (double el = -15; el <= 15.01; el += ring_deg) {
    for (double az = -50; az <= 50; az += 0.2) {
      const double e = el * M_PI / 180, a = az * M_PI / 180;
      const Vec3 dir(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      const Vec3 p = dir * (d / dir.x());
      if (p.y() >= y_min && p.y() <= y_max) points.push_back(p.cast<float>());
    }
  }
  return points;
}

TEST(DepthSurface, WithoutPointsItIsTheFixedSurface) {
  const ViewSpec spec = perspective();
  const DepthSurface surface(spec);
  const auto view = surface.update({}, Pose::Identity());
  ViewSpec fixed_spec = spec;
  fixed_spec.depth = Depth::kFixed;
  const auto fixed = View::create(fixed_spec);
  std::vector<float> x(spec.width), y(spec.width), z(spec.width), fx(spec.width), fy(spec.width), fz(spec.width);
  std::vector<uint8_t> ok(spec.width), fok(spec.width);
  for (int v = 0; v < spec.height; v += 7) {
    view->row_points(v, x.data(), y.data(), z.data(), ok.data());
    fixed->row_points(v, fx.data(), fy.data(), fz.data(), fok.data());
    for (int u = 0; u < spec.width; ++u) {
      ASSERT_EQ(ok[u], fok[u]);
      EXPECT_NEAR(x[u], fx[u], 1e-4);
      EXPECT_NEAR(y[u], fy[u], 1e-4);
      EXPECT_NEAR(z[u], fz[u], 1e-4);
    }
  }
  EXPECT_EQ(view->measured_fraction(), 0);
}

TEST(DepthSurface, RingsOnAWallAreJoinedAndNonFinitePointsCounted) {
  const ViewSpec spec = perspective();
  const DepthSurface surface(spec);
  auto points = wall_rings(2.0, 2.0);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  points.push_back({nan, 0, 0});
  points.push_back({1, inf, 0});
  DepthStats stats;
  const auto view = surface.update(points, Pose::Identity(), &stats);
  EXPECT_EQ(stats.non_finite, 2u);
  EXPECT_EQ(stats.points, points.size());
  EXPECT_GT(stats.filled_pixels, stats.splatted_pixels);  // rings ~9 px apart in this view
  // Between the rings the surface is the wall: x = 2 for every pixel within +-14 deg.
  for (int v = 26; v < 74; ++v) {
    for (int u = 40; u < 160; ++u) {
      Vec3 p;
      ASSERT_TRUE(view->pixel_to_point(u, v, p));
      EXPECT_NEAR(p.x(), 2.0, 0.01) << u << "," << v;
      EXPECT_EQ(view->measured_at(u, v), 255);
    }
  }
}

TEST(DepthSurface, AStepIsNotBridgedAndFarFromSamplesTheFixedSurfaceReturns) {
  const ViewSpec spec = perspective();
  const DepthSurface surface(spec);
  // A near wall on the left half (x = 1.5, y > 0) and a far one on the right (x = 6, y < 0,
  // behind the fixed plane at 5 m):
  // the columns between their samples must not be filled with a surface across the step.
  auto points = wall_rings(1.5, 2.0, 0.02, 10);
  const auto far = wall_rings(6.0, 2.0, -10, -0.1);
  points.insert(points.end(), far.begin(), far.end());
  DepthStats stats;
  const auto view = surface.update(points, Pose::Identity(), &stats);
  for (int v = 30; v < 70; ++v) {
    int unmeasured = 0;  // the columns between the two walls' last samples
    for (int u = 0; u < spec.width; ++u) {
      if (view->measured_at(u, v) != 255) {
        ++unmeasured;
        continue;
      }
      Vec3 p;
      ASSERT_TRUE(view->pixel_to_point(u, v, p));
      // Every measured point is on one wall or the other, never in between.
      EXPECT_TRUE(std::abs(p.x() - 1.5) < 0.02 || std::abs(p.x() - 6.0) < 0.05) << u << "," << v << " x " << p.x();
    }
    EXPECT_LE(unmeasured, 4) << "row " << v;
  }
  // Above +15 deg elevation nothing was measured: the top row (26.6 deg) is the fixed plane
  // at 5 m. Above the far wall, behind that plane, a band fades from one to the other
  // without a jump; above the near wall, an object in front of it, the edge stays a step.
  Vec3 top;
  ASSERT_TRUE(view->pixel_to_point(100, 0, top));
  EXPECT_NEAR(top.x(), 5.0, 1e-3);
  EXPECT_EQ(view->measured_at(100, 0), 0);
  float previous = view->range_at(150, 50);
  for (int v = 49; v >= 0; --v) {
    const float r = view->range_at(150, v);
    EXPECT_LT(std::abs(r - previous), 0.1f * previous) << "row " << v;  // a fade, no step
    previous = r;
  }
  EXPECT_EQ(view->measured_at(50, 15), 0) << "no fade above the near wall";
  Vec3 above_near;
  ASSERT_TRUE(view->pixel_to_point(50, 15, above_near));
  EXPECT_NEAR(above_near.x(), 5.0, 1e-3);
}

// Every view type stands on measured depth the same way (the generic projection path): a
// cylindrical panorama of radius 5 inside a round room of radius 3 sampled like a lidar.
TEST(DepthSurface, APanoramaStandsOnTheMeasuredRoom) {
  ViewSpec spec;
  spec.name = "pano";
  spec.type = ViewType::kCylindrical;
  spec.width = 360;
  spec.height = 90;
  spec.radius = 5;
  spec.vfov_deg = 40;
  spec.depth = Depth::kMeasured;
  std::vector<Eigen::Vector3f> points;
  for (double az = 0; az < 360; az += 0.2) {
    for (double el = -15; el <= 15.01; el += 2) {  // a VLP-16's rings
      const double a = az * M_PI / 180, e = el * M_PI / 180;
      points.emplace_back(float(3 * std::cos(a)), float(3 * std::sin(a)), float(3 * std::tan(e)));
    }
  }
  const auto view = DepthSurface(spec).update(points, Pose::Identity());
  size_t on_room = 0, rows = 0;
  for (int v = 14; v < 76; ++v) {  // within the rings' +-15 deg (rows 12 .. 77)
    for (int u = 0; u < spec.width; ++u) {
      Vec3 p;
      ASSERT_TRUE(view->pixel_to_point(u, v, p));
      ++rows;
      on_room += std::abs(std::hypot(p.x(), p.y()) - 3.0) < 0.02;
    }
  }
  EXPECT_GT(double(on_room) / double(rows), 0.99);
  EXPECT_GT(view->measured_fraction(), 0.7);  // +-15 of the +-20 deg
}

// The same points make the same surface whatever the view's resolution: the surface is
// built on a lattice of a fixed angle (surface_lattice.h). A reviewer found the share on
// measured depth falling with resolution when it was built per view pixel (99 % at
// 512 x 256, 77 % at 4096 x 2048). An equirectangular panorama in a round room of radius 3
// sampled like a VLP-16, at 512 x 256 and 2048 x 1024 over 180 deg of azimuth.
TEST(DepthSurface, TheSurfaceDoesNotDependOnTheViewsResolution) {
  std::vector<Eigen::Vector3f> points;
  for (double az = 0; az < 360; az += 0.2) {
    for (double el = -15; el <= 15.01; el += 2) {
      const double a = az * M_PI / 180, e = el * M_PI / 180;
      points.emplace_back(float(3 * std::cos(a)), float(3 * std::sin(a)), float(3 * std::tan(e)));
    }
  }
  const auto measure = [&](int w, DepthOptions options, int* cell) {
    ViewSpec spec;
    spec.name = "pano";
    spec.type = ViewType::kEquirectangular;
    spec.azimuth_span_deg = 180;  // 0.35 and 0.09 deg pixels
    spec.width = w;
    spec.height = w / 2;
    spec.radius = 5;
    spec.depth = Depth::kMeasured;
    const DepthSurface surface(spec, options);
    *cell = surface.lattice().cell;
    const auto view = surface.update(points, Pose::Identity());
    // Within the rings' +-15 deg every pixel on the room's wall.
    size_t on_room = 0, pixels = 0;
    for (int v = 0; v < spec.height; ++v) {
      const double el = 90 - 180.0 * (v + 0.5) / spec.height;
      if (std::abs(el) > 14) continue;
      for (int u = 0; u < spec.width; u += std::max(1, w / 512)) {
        Vec3 p;
        EXPECT_TRUE(view->pixel_to_point(u, v, p));
        ++pixels;
        on_room += std::abs(std::hypot(p.x(), p.y()) - 3.0) < 0.02;
      }
    }
    return std::make_pair(view->measured_fraction(), double(on_room) / double(pixels));
  };
  int small_cell = 0, big_cell = 0, per_pixel_cell = 0;
  const auto [small_share, small_on_room] = measure(512, {}, &small_cell);
  const auto [big_share, big_on_room] = measure(2048, {}, &big_cell);
  DepthOptions per_pixel;
  per_pixel.lattice_cell_deg = 0;  // the view's own pixels, as before the lattice
  const auto [old_share, old_on_room] = measure(2048, per_pixel, &per_pixel_cell);
  std::cout << "measured share: 512 px " << small_share << ", 2048 px " << big_share << " (per pixel " << old_share
            << "); on the wall " << small_on_room << " / " << big_on_room << " (" << old_on_room << ")\n";
  EXPECT_EQ(small_cell, 1);  // 0.35 deg pixels: coarser than the lattice
  EXPECT_EQ(big_cell, 3);    // 0.09 deg pixels: cells of 0.26 deg
  EXPECT_EQ(per_pixel_cell, 1);
  EXPECT_NEAR(big_share, small_share, 0.02);
  EXPECT_GT(small_on_room, 0.99);
  EXPECT_GT(big_on_room, 0.99);
}

// Depth for every pixel (a dense depth image, the goldens' exact depth) is finer than a
// cell: the surface is then made on the view's own pixels, so an object's edge stays where
// it is (on the lattice the pixels beside it stood at its range: the golden bird's-eye at
// 800 x 800 on exact depth lost 12 dB that way).
TEST(DepthSurface, DepthForEveryPixelStaysOnTheViewsPixels) {
  const ViewSpec spec = perspective(1200, 600);
  const DepthSurface surface(spec);
  ASSERT_GE(surface.lattice().cell, 2);
  DepthOptions per_pixel;
  per_pixel.lattice_cell_deg = 0;
  const DepthSurface on_pixels(spec, per_pixel);
  std::vector<Eigen::Vector3f> points;  // a box 1.5 m ahead in the middle, the wall at 3 m
  for (int v = 0; v < spec.height; ++v) {
    for (int u = 0; u < spec.width; ++u) {
      Vec3 d;
      ASSERT_TRUE(surface.rays().view->pixel_to_direction(u, v, d));
      const double x = std::abs(u - 600) < 100 ? 1.5 : 3.0;
      points.push_back((d * (x / d.x())).cast<float>());
    }
  }
  const auto view = surface.update(points, Pose::Identity());
  const auto reference = on_pixels.update(points, Pose::Identity());
  for (int v = 0; v < spec.height; v += 5) {
    for (int u = 490; u < 510; ++u) ASSERT_EQ(view->range_at(u, v), reference->range_at(u, v)) << u << "," << v;
  }
}

// Every view type's projection lines up with its lattice (else the surface would fall back
// to the view's pixels, at their cost).
TEST(DepthSurface, EveryViewTypeHasALattice) {
  for (const ViewType type : {ViewType::kPerspective, ViewType::kBirdseye, ViewType::kCylindrical, ViewType::kMercator,
                              ViewType::kEquirectangular, ViewType::kFisheye}) {
    ViewSpec spec = perspective(1200, 600);
    spec.type = type;
    spec.azimuth_span_deg = 90;  // panoramas: 0.075 deg pixels, as the perspective's
    spec.fov_deg = 60;           // fisheye: 0.1 deg pixels
    spec.radius = 5;
    spec.vfov_deg = 60;
    spec.height_m = 4;
    spec.lat_min_deg = -60;
    spec.lat_max_deg = 60;
    const DepthSurface surface(spec);
    EXPECT_GE(surface.lattice().cell, 2) << to_string(type);
    EXPECT_LE(surface.lattice().cells->width * surface.lattice().cell, spec.width + surface.lattice().cell);
  }
}

TEST(DepthSurface, ColumnPointsSplatAsStretchesMakeUnbrokenLines) {
  // A column of points 5 cm apart 1 m ahead: ~3 deg apart, several pixels; as stretches of
  // 5 cm every row between its ends holds a sample, in any view type.
  std::vector<Eigen::Vector3f> column;
  for (int k = 0; k <= 8; ++k) column.emplace_back(1.f, 0.2f, -0.4f + 0.05f * k);
  for (const ViewType type : {ViewType::kPerspective, ViewType::kEquirectangular}) {
    ViewSpec spec = perspective(400, 200);
    spec.type = type;
    spec.azimuth_span_deg = 90;
    spec.lat_min_deg = -45;
    spec.lat_max_deg = 45;
    const auto rays = make_view_rays(View::create(spec));
    DepthStats points_stats, stretch_stats;
    const std::vector<float> dots = splat_points(*rays, column, Pose::Identity(), points_stats);
    const std::vector<float> lines =
        splat_stretches(*rays, column, Pose::Identity(), Eigen::Vector3f::UnitZ(), 0.05f, stretch_stats);
    EXPECT_EQ(points_stats.splatted_pixels, 9u) << to_string(type);
    int top = rays->height, bottom = -1, rows_hit = 0;
    for (int v = 0; v < rays->height; ++v) {
      bool hit = false;
      for (int u = 0; u < rays->width; ++u) {
        const float r = lines[size_t(v) * rays->width + u];
        if (r == 0.f) continue;
        hit = true;
        EXPECT_GE(r, std::hypot(1.f, 0.2f) - 1e-3f);  // between its ends' ranges
        EXPECT_LE(r, std::hypot(1.f, 0.2f, 0.45f) + 1e-3f);
      }
      if (hit) top = std::min(top, v), bottom = std::max(bottom, v), ++rows_hit;
    }
    EXPECT_GT(bottom - top, 40) << to_string(type);  // 0.45 m at 1 m: ~24 deg
    EXPECT_EQ(rows_hit, bottom - top + 1) << to_string(type);
    EXPECT_GT(stretch_stats.splatted_pixels, 4 * points_stats.splatted_pixels) << to_string(type);
    // Bad points are counted, not drawn.
    DepthStats bad;
    EXPECT_EQ(splat_stretches(*rays, {Eigen::Vector3f(NAN, 0, 0), Eigen::Vector3f(-1, 0, 0)}, Pose::Identity(),
                              Eigen::Vector3f::UnitZ(), 0.05f, bad),
              std::vector<float>(rays->size(), 0.f));
    EXPECT_EQ(bad.non_finite, 1u);
    EXPECT_EQ(bad.outside_view, 1u);
  }
}

TEST(DepthSurface, MeasuredViewsAreRejectedWhereTheSpecIsInvalid) {
  ViewSpec spec = perspective();
  spec.hfov_deg = 0;
  EXPECT_THROW(DepthSurface{spec}, std::invalid_argument);
}

// One camera looking along +x from the origin; a small box of points 1 m ahead hides the
// wall behind it: the view's pixels on the wall behind the box are black, the rest not.
TEST(DepthOcclusion, AHiddenSurfacePointIsBlackNotTheOccludersColour) {
  Rig rig("base");
  Camera cam;
  cam.name = "cam";
  cam.model = CameraModel(PinholeRadtan(200, 200, 199.5, 149.5));
  cam.width = 400;
  cam.height = 300;
  cam.T_parent_cam = make_pose(Vec3(0, 0, 0), 0, 0, 0);
  cam.T_parent_cam.linear() = cam.T_parent_cam.linear() * R_view_optical();
  rig.add_camera(cam);
  // The view stands 0.5 m to the left of the camera and sees the wall x = 4 past the box.
  ViewSpec spec = perspective(100, 60);
  spec.frame = "base";
  spec.position = Vec3(0, 0.5, 0);
  // Sampled like a lidar at the view's place (every 0.5 deg): the box x = 1, |y|, |z| <= 0.3,
  // and the wall x = 4, also where the box hides it from the camera.
  std::vector<Eigen::Vector3f> points;  // in "base"
  const Vec3 lidar(0, 0.5, 0);
  for (double az = -50; az <= 50; az += 0.5) {
    for (double el = -30; el <= 30; el += 0.5) {
      const Vec3 dir(1, std::tan(az * M_PI / 180), std::tan(el * M_PI / 180));
      const Vec3 on_box = lidar + dir * 1.0;
      const bool box = std::abs(on_box.y()) <= 0.3 && std::abs(on_box.z()) <= 0.3;
      points.push_back((lidar + dir * (box ? 1.0 : 4.0)).cast<float>());
    }
  }
  const DepthSurface surface(spec);
  const auto view = surface.update(points, spec.T_frame_view().inverse());
  const Occlusion occlusion =
      view_occlusion(CameraRangeImages(rig, ViewOcclusionOptions{}.cell_deg), *view, points, spec.T_frame_view().inverse());
  const FusionMap with = build_map(rig, *view, MapPrecision::kExact, Sampling::kBilinear, &occlusion);
  const FusionMap without = build_map(rig, *view, MapPrecision::kExact, Sampling::kBilinear);
  // The wall point straight behind the box as the camera sees it, (4, 0, 0), seen from the view.
  Vec2 uv;
  ASSERT_TRUE(view->point_to_pixel(spec.T_frame_view().inverse() * Vec3(4, 0, 0), uv));
  const size_t behind = size_t(std::lround(uv.y())) * with.width + size_t(std::lround(uv.x()));
  EXPECT_EQ(without.primary[behind].cam, 0) << "without occlusion the box's colour is painted there";
  EXPECT_EQ(with.primary[behind].cam, kNoCamera);
  // The box itself and the wall beside it stay.
  ASSERT_TRUE(view->point_to_pixel(spec.T_frame_view().inverse() * Vec3(1, 0, 0), uv));
  EXPECT_EQ(with.primary[size_t(std::lround(uv.y())) * with.width + size_t(std::lround(uv.x()))].cam, 0);
  ASSERT_TRUE(view->point_to_pixel(spec.T_frame_view().inverse() * Vec3(4, 2.0, 0), uv));
  EXPECT_EQ(with.primary[size_t(std::lround(uv.y())) * with.width + size_t(std::lround(uv.x()))].cam, 0);
  EXPECT_LT(with.coverage(), without.coverage());
}

// A depth camera's image as points: each pixel's value along its ray, 0 and too far
// dropped, every `step`-th pixel each way; an image of the wrong size or scale is refused.
TEST(DepthImagePoints, EachPixelsDepthAlongItsRay) {
  Camera cam;
  cam.name = "front_depth";
  cam.width = 4, cam.height = 2;
  cam.model = CameraModel(PinholeRadtan(2, 2, 1.5, 0.5));
  // Depths in mm, little-endian: 2 m everywhere but a 0 (nothing measured) and 50 m.
  std::vector<uint16_t> mm = {2000, 0, 2000, 2000, 2000, 2000, 50000, 2000};
  std::vector<uint8_t> bytes;
  for (uint16_t v : mm) bytes.push_back(uint8_t(v & 0xff)), bytes.push_back(uint8_t(v >> 8));
  const DepthImage image{bytes, 1000};
  const auto points = depth_image_points(image, cam, 0, 10);
  ASSERT_EQ(points.size(), 6u);
  for (const auto& p : points) EXPECT_NEAR(p.z(), 2.0f, 1e-5f);
  EXPECT_NEAR(points.front().x(), (0 - 1.5) / 2 * 2.0, 1e-5);  // pixel (0, 0)
  EXPECT_NEAR(points.front().y(), (0 - 0.5) / 2 * 2.0, 1e-5);
  EXPECT_EQ(depth_image_points(image, cam, 2, 10).size(), 2u);  // (0, 0) and (2, 0)
  EXPECT_EQ(depth_image_points(image, cam, 1, 100).size(), 7u);

  const std::vector<uint8_t> short_data(bytes.begin(), bytes.end() - 2);
  try {
    depth_image_points(DepthImage{short_data, 1000}, cam, 1, 10);
    ADD_FAILURE() << "a short image was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("camera 'front_depth': 14 bytes for 8 16-bit pixels"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(depth_image_points(DepthImage{bytes, 0}, cam, 1, 10), std::invalid_argument);
  EXPECT_THROW(depth_image_points(DepthImage{bytes, NAN}, cam, 1, 10), std::invalid_argument);
}

}  // namespace
}  // namespace omniview
