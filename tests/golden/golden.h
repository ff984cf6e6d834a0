// Golden-image harness: render a scene whose geometry coincides with a view's surface
// through a rig, build and apply the view's map, and compare with the texture sampled at
// the view's surface points.
#pragma once

#include <string>

#include <opencv2/core/mat.hpp>

#include "core/map/fusion_map.h"
#include "core/rig/rig.h"
#include "core/synthetic/scene.h"
#include "core/view/view_spec.h"

namespace omniview::golden {

struct Score {
  double psnr_db = 0;   // over pixels the map covers and the view has a surface point
  double coverage = 0;  // fraction of the view's surface pixels some camera covers
  cv::Mat rendered, reference;
};

// `render_rig` renders the camera images; `map_rig` (usually the same) builds the map, so a
// test can feed a wrong calibration and see the damage. The scene is in `world_frame`.
Score run(const synthetic::Scene& scene, const Rig& render_rig, const Rig& map_rig, const ViewSpec& view,
          const std::string& world_frame, bool grey_cameras = false, int out_channels = 3);

inline Score run(const synthetic::Scene& scene, const Rig& rig, const ViewSpec& view, const std::string& world_frame,
                 bool grey_cameras = false, int out_channels = 3) {
  return run(scene, rig, rig, view, world_frame, grey_cameras, out_channels);
}

// The bundled example rig (two 210 deg fisheyes, the back one rolled 3 deg).
Rig example_rig();

}  // namespace omniview::golden
