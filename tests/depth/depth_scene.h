// The furnished room the depth-aware view tests stand the Spot-like rig in: boxes and
// pillars between 0.8 and 4 m of the robot, the floor, walls past 5 m, no ceiling; the truth of a view
// is what a camera at the view's own pose sees (ray-cast), not the texture on its surface.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/cloud/point_cloud.h"
#include "core/map/fusion_map.h"
#include "core/rig/rig.h"
#include "core/synthetic/scene.h"
#include "core/view/view_spec.h"

namespace omniview::test {

// World z = 0 is the floor; the body stands 0.5 m above it at the origin.
synthetic::Scene furnished_room();
Pose T_world_body();

// A ring of four cameras 90 deg apart, 0.3 m out from the body's centre, pitched 20 deg
// down, each 104 deg wide (a car's or a custom robot's surround rig), with the "lidar" and
// "world" frames of rig_in_world.
std::shared_ptr<Rig> ring_of_four();

// The views the depth tests build (fixed surfaces; set depth to measure): a bird's-eye view
// 4 m over the floor, a front view as config/spot.yaml's (at the front cameras, pitched down,
// the floor cut in), a 360 deg panorama on a 3 m sphere with the floor cut in.
ViewSpec birdseye_spec(const std::string& name = "birdseye");
ViewSpec front_spec(const std::string& name = "front");
ViewSpec panorama_spec(const std::string& name = "panorama");

// The view as a camera at its pose would see it: grey (luma, one ray per pixel centre),
// the hit point in the view frame (NaN where the ray hits nothing), and 255 where some rig
// camera sees that point (inside its image, not hidden).
struct ViewTruth {
  cv::Mat grey;                        // CV_8UC1
  cv::Mat seen;                        // CV_8UC1, 255 / 0
  std::vector<Eigen::Vector3f> points; // row-major, view frame
};
ViewTruth view_truth(const synthetic::Scene& scene, const Rig& rig, const ViewSpec& spec);

// A map's picture against the truth: PSNR over the pixels some camera sees (a black pixel
// there counts as wrong), and the share of the pixels no camera sees that the map paints.
struct DepthScore {
  double psnr_db = 0;
  double unseen_painted = 0;  // fraction of unseen pixels with a camera
  size_t seen = 0, unseen = 0;
};
DepthScore score(const FusionMap& map, const std::vector<cv::Mat>& images, const ViewTruth& truth);

}  // namespace omniview::test
