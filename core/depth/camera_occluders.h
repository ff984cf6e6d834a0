// Per-camera occlusion for a measured-depth view, from the same points the view stands on:
// each camera gets the cloud colourer's depth buffer of those points (core/cloud: the same
// projection, splat and "covered from both sides" rule, ColourOptions' cell, reach and
// tolerances), handed to build_map, which then takes no camera's colour for a surface point
// that camera sees hidden behind a nearer surface.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/cloud/colourer.h"
#include "core/depth/measured_depth_view.h"
#include "core/map/occlusion.h"
#include "core/rig/rig.h"

namespace omniview {

// `points` in `points_frame` (a frame of the rig) moved by T_frame_points; non-finite points
// are skipped. Throws std::invalid_argument when the frame is not connected to the rig's
// cameras.
Occlusion camera_occluders(const Rig& rig, const std::vector<Eigen::Vector3f>& points, const std::string& points_frame,
                           const ColourOptions& options = {}, const Pose& T_frame_points = Pose::Identity());

// The colourer's occlusion settings for views: a view's measured surface is dense (its gaps
// filled), so cells of 0.2 deg (about a pixel of a 90 deg, 640 px camera) and a reach of two
// cells keep the black wedges behind objects as narrow as the cameras' own; the colourer's
// 1 deg cells and 4 deg reach, made to bridge a lidar's rings, blacken visible floor and
// wall next to every object (the golden test measured 24 dB against 35 dB here).
ColourOptions view_occlusion_options();

// The occlusion a measured-depth view is mapped with: the depth buffers of the measured
// points (`points`, placed in the view frame by T_view_points) together with the view's own
// measured surface, whose gaps between the points are filled already (a lidar's rings alone,
// 2 deg apart, let the floor behind a pillar show through between them), sampled every
// `surface_step` pixels; the blend band left out of the test (Occlusion::judged).
Occlusion view_occlusion(const Rig& rig, const MeasuredDepthView& view, const std::vector<Eigen::Vector3f>& points,
                         const Pose& T_view_points, const ColourOptions& options = view_occlusion_options(),
                         int surface_step = 2);

}  // namespace omniview
