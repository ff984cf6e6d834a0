// Where a blend view puts its seams. Spot's front cameras overlap heavily: feathering by
// the distance to each camera's border alone mixed them 50/50 across most of the overlap,
// which doubles everything off the surface. The map now leans toward the camera whose
// pixel is nearer its image centre and narrows the band where parallax is large.
#include <gtest/gtest.h>

#include <iostream>

#include "core/map/usable_region.h"
#include "core/view/view.h"
#include "tests/golden/golden.h"
#include "tests/golden/thresholds.h"

namespace omniview {
namespace {

// config/spot.yaml's front view.
ViewSpec spot_front() {
  ViewSpec v = default_view_spec(ViewType::kPerspective);
  v.name = "front";
  v.width = 1024, v.height = 512;
  v.frame = "body";
  v.position = Vec3(0.42, 0, 0);
  v.pitch_deg = 25;
  v.hfov_deg = 120;
  v.distance = 3;
  v.feather_px = 30;
  return v;
}

// A map entry's position in its camera's full-size image.
cv::Point position(const MapEntry& e, const cv::Size& size) {
  return {static_cast<int>(e.offset % size.width) + (e.fx >= 128), static_cast<int>(e.offset / size.width) + (e.fy >= 128)};
}

TEST(SeamPlacement, SpotFrontBlendsLessOfTheOverlapThanFeatheringAlone) {
  const Rig rig = golden::spot_like_rig();
  const ViewSpec spec = spot_front();
  const FusionMap map = build_map(rig, *View::create(spec), MapPrecision::kAdaptive, Sampling::kBilinear);
  std::vector<cv::Mat> feather;
  for (const auto& c : rig.cameras()) feather.push_back(feather_weights(c, spec.feather_px));
  // Pixels where both cameras carry at least 1/16 of the result, by the map and by the
  // feather-only rule (w1 / (w1 + w2) of the same two cameras at the same pixels).
  size_t overlap = 0, blended = 0, blended_by_feather = 0;
  for (size_t i = 0; i < map.primary.size(); ++i) {
    const MapEntry a = map.primary[i], b = map.secondary[i];
    if (a.cam == kNoCamera || b.cam == kNoCamera) continue;
    ++overlap;
    const uint16_t w = map.primary_weight[i];
    blended += w >= 16 && w <= 240;
    const float fa = feather[a.cam].at<float>(position(a, map.camera_sizes[a.cam]));
    const float fb = feather[b.cam].at<float>(position(b, map.camera_sizes[b.cam]));
    const float share = fa + fb > 0 ? fa / (fa + fb) : 1;
    blended_by_feather += share >= 1 / 16.0f && share <= 15 / 16.0f;
  }
  std::cout << "[ seams ] spot front: overlap " << 100.0 * overlap / map.primary.size() << " % of the view, blended "
            << 100.0 * blended / overlap << " % of it (feathering alone: " << 100.0 * blended_by_feather / overlap
            << " %)\n";
  ASSERT_GT(overlap, map.primary.size() / 10) << "the front cameras overlap heavily";
  EXPECT_LT(blended, blended_by_feather / 4);
}

TEST(SeamPlacement, SeamsStayInvisibleOnTheSurface) {
  // Where the scene lies on the surface, cameras agree wherever the seam goes: the blend
  // view must match the truth as well as the nearest-centre one does.
  const Rig rig = golden::spot_like_rig();
  ViewSpec blend = spot_front();
  ViewSpec nearest = blend;
  nearest.fusion = Fusion::kNearestCentre;
  const auto scene = golden::matching_scene(rig, blend, "body");
  golden::Renders renders(scene, rig, "body");
  const auto b = golden::run(renders, rig, blend, golden::Inputs::kGrey, 1);
  const auto n = golden::run(renders, rig, nearest, golden::Inputs::kGrey, 1);
  golden::report("spot front, blend", b);
  EXPECT_GT(b.psnr_db, kSpotWallBoundDb);
  EXPECT_GT(b.psnr_db, n.psnr_db - 1);
}

}  // namespace
}  // namespace omniview
