// Colouring a point cloud from a rig's cameras (README: "Coloured point clouds").
//
// Every point is moved to where it was, relative to each camera, when that camera's image
// was taken (the robot's motion between the lidar's and the cameras' stamps comes from a
// Trajectory; without one the robot is assumed still), projected with the camera's own
// model in a batch per camera (one std::visit per camera, then a loop the compiler
// inlines and vectorises), and kept where the camera's usable region (image, mask, lens
// field of view) has it. Occlusion: each camera gets a depth buffer splatted from the cloud
// itself (nearest range per cell, at an angular cell size matched to the lidar's sampling,
// see ColourOptions::occlusion_cell_deg); a point farther than a surface that covers its
// cell (samples nearer than it on both sides, or in the cell) takes no colour from that
// camera. Fusion as for views: the camera whose
// pixel is nearest its image centre, or a feathered blend. Grey cameras give grey.
//
// Flags per point (PointCloud::flags, cloud_flags): kColoured, kOccluded (some camera
// would image it but a nearer surface hides it there, and none coloured it), kSelf (left
// as the self-filter set it: such points take no colour but still hide what is behind
// them, as the robot's legs do). PointCloud::camera: the camera that coloured the point
// (the heaviest one when blending), kNoCamera otherwise. Uncoloured points keep their
// input colour, or 0 when the cloud had none.
#pragma once

#include <chrono>
#include <memory>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/cloud/point_cloud.h"
#include "core/cloud/trajectory.h"
#include "core/rig/rig.h"
#include "core/view/view_spec.h"

namespace omniview {

struct ColourOptions {
  Fusion fusion = Fusion::kNearestCentre;
  double feather_px = 24;  // blend: distance from a camera's usable border at full weight
  bool occlusion = true;
  // Depth buffer cell, as an angle, and how far a covering surface's samples may lie on
  // either side of a cell. A VLP-16 samples 0.1-0.4 deg apart along a ring and 2 deg between
  // rings, which a camera nearer an object than the lidar sees farther apart: with 1.5 deg
  // cells and a 4 deg reach (3 cells), a nearer surface's rings on both sides of a cell
  // cover it, while a surface seen at a grazing angle, whose nearer ring lies on one side
  // only (or in the cell itself, which is left out), does not hide itself. Cells stay small
  // next to real occluders (a 0.3 m post at 5 m spans 3.4 deg) and few, so the buffer costs
  // little. 1 deg cells left 4.6 % of the points hidden 0.4-0.8 m behind a room's surfaces
  // coloured (a dense cloud seen by Spot's cameras, tests/cloud/hidden_points_test.cc),
  // 1.5 deg 1.9 % with every visible point of a VLP-16 scan still coloured; 2 deg 1.5 %,
  // but 0.3 % of those visible points lost.
  double occlusion_cell_deg = 1.5;
  double occlusion_reach_deg = 4.0;
  // A point is hidden when farther than the surface covering its cell by more than
  // rel * range + abs (core/map/occlusion.h's hidden_behind). A surface seen at a slant
  // changes depth across a cell; the covering depth allows for one cell's change
  // (occluding_depth, camera_pass.cc), so the tolerance need only absorb what that leaves
  // (a concave corner's nearer neighbours, uneven sampling). At 10 % + 0.1 m it let through
  // points up to 0.5 m behind a surface 4 m away: 25 % of the points 0.4-0.8 m behind a
  // sphere of 4 m around two fisheyes took its colour (tests/cloud/hidden_points_test.cc).
  // 3 % + 0.08 m keeps points 0.4 m behind a surface up to 10 m away hidden and meets the
  // issue's goal on a 5 cm voxel cloud of the room (1.9 % hidden coloured; 0.12 m: 2.2 %);
  // the VLP-16 scans of colour_test leave 13 visible points of 17921 uncoloured (was 1).
  float occlusion_tolerance_rel = 0.03f;
  float occlusion_tolerance_m = 0.08f;
  // Move points for the robot's motion between stamps (needs a Trajectory).
  bool time_sync = true;
  // Per-point times are grouped into bins of this length, one motion correction each:
  // at 2 m/s and 2 ms a point moves 4 mm, well under a pixel's footprint at lidar ranges.
  double motion_bin_s = 0.002;
};

// What the cameras took: one image per rig camera (CV_8UC1 or CV_8UC3 BGR, the camera's
// calibrated size; an empty Mat when that camera has none) and when.
struct CameraImages {
  std::vector<cv::Mat> images;
  // One per image; empty: all at the cloud's stamp.
  std::vector<std::chrono::system_clock::time_point> stamps;
};

struct ColourStats {
  size_t points = 0;
  size_t coloured = 0;
  size_t occluded = 0;       // not coloured: hidden in every camera that would image it
  size_t self_filtered = 0;  // kSelf on input
  size_t unseen = 0;         // no camera images it (or not finite)
};

namespace cloud_internal {
struct CameraPass;  // colourer_internal.h
}

class CloudColourer {
 public:
  // Precomputes each camera's usable region (and feather weights when blending) for `rig`;
  // make a new colourer when the rig changes.
  explicit CloudColourer(std::shared_ptr<const Rig> rig);
  ~CloudColourer();
  CloudColourer(const CloudColourer&) = delete;
  CloudColourer& operator=(const CloudColourer&) = delete;

  // Colours `cloud` in place (rgb, flags, camera). The cloud's frame must be connected to
  // the rig's frames; `motion` (optional) gives the rig's default frame in a fixed frame
  // over time. Throws std::invalid_argument naming the frame, or a camera whose image has
  // the wrong size.
  ColourStats colour(PointCloud& cloud, const CameraImages& images, const ColourOptions& options,
                     const Trajectory* motion = nullptr);

  const Rig& rig() const { return *rig_; }

 private:
  struct CameraSetup;
  std::shared_ptr<const Rig> rig_;
  std::vector<std::shared_ptr<CameraSetup>> cameras_;
  using CameraPass = cloud_internal::CameraPass;
  // colour()'s steps (colourer.cc says what each does).
  Pose check_inputs(const PointCloud& cloud, const CameraImages& input) const;
  void deskew(const PointCloud& cloud, const Pose& T_base_cloud, const Trajectory* motion, double bin_s);
  void project_into_cameras(const PointCloud& cloud, const CameraImages& input, const ColourOptions& options,
                            const Pose& T_base_cloud, const Trajectory* motion);
  ColourStats fuse(PointCloud& cloud, const CameraImages& input, const ColourOptions& options) const;
  // Phase 2 of colour() on points [begin, end): nearest-centre fusion, or a feathered blend.
  // Each sets every point's flags and camera, and counts them (all but ColourStats::points).
  ColourStats nearest_centre(PointCloud& cloud, const CameraImages& input, const ColourOptions& options,
                             size_t begin, size_t end) const;
  ColourStats blend(PointCloud& cloud, const CameraImages& input, const ColourOptions& options, size_t begin,
                    size_t end) const;
  // Scratch, reused between calls.
  std::vector<float> x_, y_, z_;  // points at the cloud's stamp, in the cloud frame
  std::vector<CameraPass> passes_;
};

}  // namespace omniview
