// Golden-image harness: render a scene whose geometry coincides with a view's surface
// through a rig, build and apply the view's map, and compare with the texture sampled at
// the view's surface points.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/map/fusion_map.h"
#include "core/rig/rig.h"
#include "core/synthetic/scene.h"
#include "core/synthetic/spot_like_rig.h"
#include "core/view/view_spec.h"

namespace omniview::golden {

// The world frame of the golden rigs (their scenes are posed in it).
inline const std::string kWorld = "base_link";

// What the cameras deliver. kMixed: even-indexed cameras greyscale, odd ones BGR.
enum class Inputs { kColour, kGrey, kMixed };

struct CameraScore {
  std::string name;
  size_t pixels = 0;    // view pixels this camera is the primary source of
  double psnr_db = 0;   // over those pixels
};

struct Score {
  double psnr_db = 0;   // over pixels the map covers and the view has a surface point
  double coverage = 0;  // fraction of the view's surface pixels some camera covers
  std::vector<CameraScore> cameras;  // per rig camera, in rig order
  cv::Mat rendered, reference;
};

// The camera images of a scene seen through a rig, rendered on first use and kept: the
// renders (3x3 rays per pixel) are most of a golden test's time, tenfold under the
// sanitizers, so runs that map the same images share one Renders. Greyscale images are
// the colour render's luma (cv::COLOR_BGR2GRAY, as the reference's luma is made).
class Renders {
 public:
  Renders(const synthetic::Scene& scene, const Rig& rig, std::string world_frame)
      : scene_(scene), rig_(rig), world_frame_(std::move(world_frame)), colour_(rig.cameras().size()),
        grey_(rig.cameras().size()) {}
  const cv::Mat& image(size_t camera, bool grey);
  const Rig& rig() const { return rig_; }
  const std::string& world_frame() const { return world_frame_; }

 private:
  const synthetic::Scene& scene_;
  const Rig& rig_;
  std::string world_frame_;
  std::vector<cv::Mat> colour_, grey_;
};

// `renders` holds the camera images; `map_rig` (usually the rig they were rendered with)
// builds the map, so a test can feed a wrong calibration and see the damage. Where a
// greyscale camera feeds a colour output, the reference is the luma in every channel (what
// apply_map delivers); with kMixed inputs use nearest fusion.
Score run(Renders& renders, const Rig& map_rig, const ViewSpec& view, Inputs inputs = Inputs::kColour,
          int out_channels = 3);

// The same, rendering the scene (in `world_frame`) through `render_rig` for this run only.
inline Score run(const synthetic::Scene& scene, const Rig& render_rig, const Rig& map_rig, const ViewSpec& view,
                 const std::string& world_frame, Inputs inputs = Inputs::kColour, int out_channels = 3) {
  Renders renders(scene, render_rig, world_frame);
  return run(renders, map_rig, view, inputs, out_channels);
}

inline Score run(const synthetic::Scene& scene, const Rig& rig, const ViewSpec& view, const std::string& world_frame,
                 Inputs inputs = Inputs::kColour, int out_channels = 3) {
  return run(scene, rig, rig, view, world_frame, inputs, out_channels);
}

// The scene coinciding with `view`'s surface, the view's frame looked up in `rig`.
synthetic::Scene matching_scene(const Rig& rig, const ViewSpec& view, const std::string& world_frame);

// Prints the overall and per-camera figures (the thresholds' comments quote them).
void report(const std::string& what, const Score& s);

// A view spec of the given type and size, everything else default.
ViewSpec view(ViewType type, int width, int height);

// A camera mounted like a view (x = optical axis, y left, z up), angles in degrees.
Camera camera(const std::string& name, CameraModel model, int width, int height, const Vec3& xyz, double yaw_deg,
              double pitch_deg, double roll_deg, double fov_deg = 0);

// The bundled example rig (config/examples/dual_fisheye: two 210 deg fisheyes, the back
// one rolled 3 deg), its panoramas (centred on the lenses 1 m above base_link, radius 3 m)
// and a copy with one camera's calibration replaced.
std::string example_dir();
Rig example_rig();
ViewSpec example_panorama(int width, int height);
Rig with_camera_pose(const Rig& rig, const std::string& name, const Pose& T_parent_cam);

// Five greyscale 640x480 pinholes placed like Spot's body cameras, in frame "body" (the
// tests put the ground 0.5 m below it). Shared with spot-mock.
using synthetic::spot_like_rig;

// Five cameras around and above a point 1 m over base_link, one per model: omni+radtan,
// double sphere, EUCM, FOV, pinhole+radtan (with k3).
Rig mixed_model_ring();

}  // namespace omniview::golden
