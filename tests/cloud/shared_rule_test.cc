// Views and clouds fuse by one rule (core/camera/centre_score.h): a point of a view's
// surface and the same point in a lidar cloud take the same camera. Checked on the
// Spot-like rig's five cameras (640x480 and rotated, overlapping at the body's corners),
// over a whole panorama's sphere and a bird's-eye view's floor, occlusion aside (these
// points hide nothing).
#include <gtest/gtest.h>

#include <iostream>

#include "cloud_scene.h"
#include "core/cloud/colourer.h"
#include "core/map/fusion_map.h"
#include "core/view/view.h"

namespace omniview {
namespace {

struct Agreement {
  size_t seen_by_view = 0;  // view pixels some camera colours
  size_t same = 0;          // ... whose surface point the cloud colours from the same camera
  size_t cloud_missed = 0;  // ... which the cloud colours from none
};

Agreement compare(const ViewSpec& spec) {
  const auto rig = test::rig_in_world(Pose::Identity());
  const auto view = View::create(spec);
  const FusionMap map = build_map(*rig, *view, MapPrecision::kExact, Sampling::kBilinear);
  // Every pixel's surface point, in the view's frame: a cloud in that frame.
  PointCloud cloud;
  cloud.frame = spec.frame;
  std::vector<int> pixel;
  const Pose T_frame_view = spec.T_frame_view();
  for (int v = 0; v < spec.height; ++v) {
    for (int u = 0; u < spec.width; ++u) {
      Vec3 p;
      if (!view->pixel_to_point(u, v, p)) continue;
      cloud.points.push_back((T_frame_view * p).cast<float>());
      pixel.push_back(v * spec.width + u);
    }
  }
  std::vector<cv::Mat> images;
  for (const auto& cam : rig->cameras()) images.emplace_back(cam.height, cam.width, CV_8UC1, cv::Scalar(128));
  CloudColourer colourer(rig);
  ColourOptions options;
  options.occlusion = false;
  options.time_sync = false;
  colourer.colour(cloud, CameraImages{images, {}}, options);
  Agreement a;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const uint8_t by_view = map.primary[pixel[i]].cam;
    if (by_view == kNoCamera) continue;
    ++a.seen_by_view;
    if (cloud.camera[i] == by_view) ++a.same;
    if (cloud.camera[i] == kNoCamera) ++a.cloud_missed;
  }
  std::cout << spec.name << ": " << a.seen_by_view << " pixels some camera sees, " << a.same
            << " take the same camera as the cloud's point there, " << a.cloud_missed << " the cloud leaves uncoloured\n";
  return a;
}

// The two paths may disagree only on the seam line itself, where two cameras score the
// same within float rounding (each path projects in float, the map from the view's frame,
// the colourer from the cloud's): a pixel wide, a few per ten thousand. With the rules the
// two had before (per-axis vs half-diagonal normalisation) 1.5 % of the panorama's and
// 1.9 % of the bird's-eye view's pixels took another camera than the cloud.
void expect_same_choice(const Agreement& a) {
  ASSERT_GT(a.seen_by_view, 1000u);
  EXPECT_GE(a.same, a.seen_by_view * 998 / 1000);
  EXPECT_LE(a.cloud_missed, a.seen_by_view / 500);
}

TEST(SharedFusionRule, APanoramasSphereTakesTheCloudsCameras) {
  ViewSpec spec = default_view_spec(ViewType::kEquirectangular);
  spec.name = "panorama";
  spec.frame = "body";
  spec.width = 512;
  spec.height = 256;
  spec.radius = 3;
  expect_same_choice(compare(spec));
}

TEST(SharedFusionRule, ABirdseyeFloorTakesTheCloudsCameras) {
  ViewSpec spec = default_view_spec(ViewType::kBirdseye);
  spec.name = "birdseye";
  spec.frame = "body";
  spec.width = 400;
  spec.height = 400;
  spec.hfov_deg = 120;
  spec.ground_z = -0.5;
  expect_same_choice(compare(spec));
}

}  // namespace
}  // namespace omniview
