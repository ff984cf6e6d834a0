// What a user asks for: one view's type, size, pose and surface parameters.
//
// Angles are stored in degrees, as the API and YAML files give them; the View classes
// convert once. Field meanings follow the README ("Conventions") and config/examples/views/.
#pragma once

#include <string>
#include <vector>

#include "core/geometry/pose.h"

namespace omniview {

enum class ViewType { kPerspective, kBirdseye, kCylindrical, kMercator, kEquirectangular, kFisheye };
enum class Fusion { kNearestCentre, kBlend };
// Where each pixel's surface point comes from: the type's fixed surface (plane, cylinder,
// sphere, ground), or the measured geometry (a lidar cloud, depth points) where there is
// some near the pixel's ray, the fixed surface elsewhere (core/depth/measured_depth_view.h).
enum class Depth { kFixed, kMeasured };

const std::vector<std::string>& view_type_names();  // in ViewType order
std::string to_string(ViewType t);
ViewType view_type_from_string(const std::string& s, const std::string& what);
std::string to_string(Fusion f);
Fusion fusion_from_string(const std::string& s, const std::string& what);
std::string to_string(Depth d);  // "fixed", "measured"
Depth depth_from_string(const std::string& s, const std::string& what);

constexpr int kMaxViewSide = 16384;
// Bounds on what a client may ask for (the config and the API share them, see validate()).
constexpr size_t kMaxViewNameLength = 64;      // view names: one word, short enough for every listing
constexpr size_t kMaxFrameNameLength = 128;    // frame and source names
constexpr double kMaxViewLength_m = 10000;     // positions, distances, radii, heights
constexpr double kMaxAngleDeg = 360;           // |yaw|, |roll| (pan wraps at +-180 anyway)
constexpr double kMinFovDeg = 0.01;            // narrowest field of view (a zoom of ~11 000)

struct ViewSpec {
  std::string name = "view";
  ViewType type = ViewType::kPerspective;
  int width = 1024;
  int height = 512;
  // The daemon source whose cameras the view fuses (empty: its first source). Offline
  // rendering has one rig and ignores it.
  std::string source;

  // Pose of the view frame (x = viewing direction, y left, z up) in `frame`.
  std::string frame;  // empty: the rig's default frame
  Vec3 position = Vec3::Zero();
  double yaw_deg = 0, pitch_deg = 0, roll_deg = 0;

  double hfov_deg = 90;        // perspective, birdseye
  double distance = 5;         // perspective: plane distance (m)
  double height_m = 3;         // birdseye: virtual camera height above the ground plane (m)
  double ground_z = 0;         // birdseye, and views with `ground`: ground plane z in `frame`
  // Every type but birdseye (whose surface is the ground): cut the surface with the ground
  // plane, so rays that meet the ground first end there (view.h). For a robot's views posed
  // in a frame whose z = 0 is the floor (Spot's `footprint`).
  bool ground = false;
  double radius = 5;           // cylindrical, mercator, equirectangular, fisheye: surface radius (m)
  double vfov_deg = 90;        // cylindrical: vertical field of view of the central cylinder
  double azimuth_span_deg = 360;  // cylindrical, mercator, equirectangular
  double lat_min_deg = -90, lat_max_deg = 90;  // equirectangular (mercator defaults to +-80)
  double fov_deg = 180;        // fisheye

  // `measured`: the surface follows measured points (offline: `omniview render --cloud`);
  // the daemon and the API do not serve it yet. `fixed` is every earlier version's surface.
  Depth depth = Depth::kFixed;

  Fusion fusion = Fusion::kNearestCentre;
  double feather_px = 24;      // blend: distance from a camera's usable border at full weight
  // blend: even out the cameras' exposures with per-camera gains measured where they overlap
  // (core/gain). Nearest-centre views have no overlap to measure and ignore it.
  bool gain_compensation = true;

  // The robot drawn into the view (perspective and birdseye: pinhole views) where the
  // daemon has a robot model for the view's source; opacity in [0, 1].
  bool overlay = false;
  double overlay_opacity = 0.8;

  // Pose of the view frame in `frame` (for birdseye, its z is ground_z + height_m).
  Pose T_frame_view() const;
};

// The defaults of a view of `type` (the YAML schema's and the API's): a bird's-eye view
// looks straight down, a mercator spans +-80 deg latitude.
ViewSpec default_view_spec(ViewType type);

// Throws std::invalid_argument with a message that names the view and the field (quoting
// at most a short prefix of any name). The one check every view passes, from the config,
// `omniview render` and the API's CreateView and UpdateView alike: names (length and
// characters), sizes, angles, fields of view, lengths, feather, opacity; NaN and infinity
// fail every bound.
void validate(const ViewSpec& spec);

}  // namespace omniview
