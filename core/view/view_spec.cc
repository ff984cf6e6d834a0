#include "core/view/view_spec.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/io/quote.h"

namespace omniview {
namespace {

constexpr double kDeg = M_PI / 180;

void check(bool ok, const ViewSpec& s, const std::string& field, const std::string& why) {
  if (!ok) throw std::invalid_argument("view " + quote_prefix(s.name) + ": " + field + " " + why);
}

bool within(double x, double lo, double hi) { return x >= lo && x <= hi; }  // false for NaN

// Source and frame names: looked up, listed and echoed in messages.
void check_name(const std::string& value, const ViewSpec& s, const std::string& field) {
  check(value.size() <= kMaxFrameNameLength, s, field,
        "may be at most " + std::to_string(kMaxFrameNameLength) + " characters, got " + quote_prefix(value));
  check(std::none_of(value.begin(), value.end(), [](char c) { return std::iscntrl(static_cast<unsigned char>(c)); }),
        s, field, "must not hold control characters, got " + quote_prefix(value));
}

std::string num(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

}  // namespace

const std::vector<std::string>& view_type_names() {
  static const std::vector<std::string> names{"perspective", "birdseye", "cylindrical",
                                              "mercator", "equirectangular", "fisheye"};
  return names;
}

std::string to_string(ViewType t) { return view_type_names().at(static_cast<size_t>(t)); }

ViewType view_type_from_string(const std::string& s, const std::string& what) {
  const auto& names = view_type_names();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == s) return static_cast<ViewType>(i);
  }
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  // `what` may be empty when the caller already says where (file:line: key:).
  throw std::invalid_argument((what.empty() ? "" : what + ": ") + "unknown view type '" + s + "' (one of: " + known + ")");
}

std::string to_string(Fusion f) { return f == Fusion::kBlend ? "blend" : "nearest"; }

Fusion fusion_from_string(const std::string& s, const std::string& what) {
  if (s == "nearest") return Fusion::kNearestCentre;
  if (s == "blend") return Fusion::kBlend;
  throw std::invalid_argument((what.empty() ? "" : what + ": ") + "unknown fusion '" + s + "' (nearest or blend)");
}

std::string to_string(Depth d) { return d == Depth::kMeasured ? "measured" : "fixed"; }

Depth depth_from_string(const std::string& s, const std::string& what) {
  if (s == "fixed") return Depth::kFixed;
  if (s == "measured") return Depth::kMeasured;
  throw std::invalid_argument((what.empty() ? "" : what + ": ") + "unknown depth '" + s +
                              "' (fixed: the view's own surface; measured: the surface follows measured points)");
}

Pose ViewSpec::T_frame_view() const {
  Vec3 p = position;
  if (type == ViewType::kBirdseye) p.z() = ground_z + height_m;
  return make_pose(p, yaw_deg * kDeg, pitch_deg * kDeg, roll_deg * kDeg);
}

ViewSpec default_view_spec(ViewType type) {
  ViewSpec s;
  s.type = type;
  if (type == ViewType::kMercator) s.lat_min_deg = -80, s.lat_max_deg = 80;
  if (type == ViewType::kBirdseye) s.pitch_deg = 90;  // straight down, forward at the top
  // Feathered blending where cameras overlap, for config views and views created through
  // the API alike: a hard seam is the first thing an operator notices. (A bare ViewSpec{}
  // keeps the paper's nearest-centre rule, which the map benchmarks measure.)
  s.fusion = Fusion::kBlend;
  return s;
}

void validate(const ViewSpec& s) {
  check(!s.name.empty(), s, "name", "must not be empty");
  check(s.name.size() <= kMaxViewNameLength, s, "name",
        "may be at most " + std::to_string(kMaxViewNameLength) + " characters long, got " +
            std::to_string(s.name.size()));
  // One word: commands take it as one argument and `omniview render` writes NAME.png.
  check(std::all_of(s.name.begin(), s.name.end(),
                    [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'; }),
        s, "name", "may hold only letters, digits, '_', '-' and '.' (no spaces or '/'), got " + quote_prefix(s.name));
  check_name(s.source, s, "source");
  check_name(s.frame, s, "frame");
  for (const auto& [field, v] : {std::pair{"width", s.width}, std::pair{"height", s.height}}) {
    check(v >= 1 && v <= kMaxViewSide, s, field,
          "must be between 1 and " + std::to_string(kMaxViewSide) + " pixels, got " + std::to_string(v));
  }
  static constexpr const char* kPositionFields[3] = {"position.x", "position.y", "position.z"};
  for (int i = 0; i < 3; ++i) {
    check(within(s.position[i], -kMaxViewLength_m, kMaxViewLength_m), s, kPositionFields[i],
          "must be within +-" + num(kMaxViewLength_m) + " m, got " + num(s.position[i]));
  }
  check(within(s.yaw_deg, -kMaxAngleDeg, kMaxAngleDeg), s, "yaw_deg",
        "(pan) must be in [-360, 360], got " + num(s.yaw_deg));
  check(within(s.roll_deg, -kMaxAngleDeg, kMaxAngleDeg), s, "roll_deg", "must be in [-360, 360], got " + num(s.roll_deg));
  // Beyond straight down (or up) the view would be upside down behind: that is a pan of 180.
  check(s.pitch_deg >= -90 && s.pitch_deg <= 90, s, "pitch_deg",
        "(tilt) must be in [-90, 90] (positive looks down), got " + num(s.pitch_deg) +
            "; to look behind, pan (yaw_deg) by 180");
  check(s.overlay_opacity >= 0 && s.overlay_opacity <= 1, s, "overlay_opacity",
        "must be in [0, 1], got " + num(s.overlay_opacity));
  check(!s.overlay || s.type == ViewType::kPerspective || s.type == ViewType::kBirdseye, s, "overlay",
        "is for perspective and birdseye views only (the robot is drawn through a pinhole), not " +
            to_string(s.type) + " views");
  check(within(s.ground_z, -kMaxViewLength_m, kMaxViewLength_m), s, "ground_z",
        "must be within +-10000 m, got " + num(s.ground_z));
  check(!s.ground || s.type != ViewType::kBirdseye, s, "ground",
        "does not apply to birdseye views (their surface is the ground plane)");
  check(!s.ground || s.position.z() > s.ground_z, s, "ground",
        "needs the view above the ground plane: position.z " + num(s.position.z()) + " m is not above ground_z " +
            num(s.ground_z) + " m (pose the view in a frame whose z = 0 is the floor, such as Spot's footprint, "
            "or set ground_z to the floor's z in '" + (s.frame.empty() ? std::string("the rig's frame") : s.frame) + "')");
  switch (s.type) {
    case ViewType::kPerspective:
      check(s.hfov_deg >= kMinFovDeg && s.hfov_deg < 180, s, "hfov_deg",
            "must be in [0.01, 180) for a perspective view, got " + num(s.hfov_deg) +
                " (use a fisheye, cylindrical or equirectangular view for wider fields)");
      check(s.distance > 0 && s.distance <= kMaxViewLength_m, s, "distance",
            "must be in (0, 10000] m, got " + num(s.distance));
      break;
    case ViewType::kBirdseye:
      check(s.hfov_deg >= kMinFovDeg && s.hfov_deg < 180, s, "hfov_deg",
            "must be in [0.01, 180), got " + num(s.hfov_deg));
      check(s.height_m > 0 && s.height_m <= kMaxViewLength_m, s, "height",
            "must be in (0, 10000] m, got " + num(s.height_m));
      break;
    case ViewType::kCylindrical:
      check(s.vfov_deg >= kMinFovDeg && s.vfov_deg < 180, s, "vfov_deg",
            "must be in [0.01, 180), got " + num(s.vfov_deg));
      break;
    case ViewType::kMercator:
      check(s.lat_min_deg > -90 && s.lat_max_deg < 90 && s.lat_min_deg < s.lat_max_deg, s,
            "lat_min_deg/lat_max_deg", "must satisfy -90 < min < max < 90 for mercator, got " +
                                          num(s.lat_min_deg) + ", " + num(s.lat_max_deg));
      break;
    case ViewType::kEquirectangular:
      check(s.lat_min_deg >= -90 && s.lat_max_deg <= 90 && s.lat_min_deg < s.lat_max_deg, s,
            "lat_min_deg/lat_max_deg", "must satisfy -90 <= min < max <= 90, got " +
                                          num(s.lat_min_deg) + ", " + num(s.lat_max_deg));
      break;
    case ViewType::kFisheye:
      check(s.fov_deg >= kMinFovDeg && s.fov_deg <= 360, s, "fov_deg",
            "must be in [0.01, 360], got " + num(s.fov_deg));
      break;
  }
  if (s.type == ViewType::kCylindrical || s.type == ViewType::kMercator ||
      s.type == ViewType::kEquirectangular) {
    check(s.azimuth_span_deg >= kMinFovDeg && s.azimuth_span_deg <= 360, s, "azimuth_span_deg",
          "must be in [0.01, 360], got " + num(s.azimuth_span_deg));
  }
  if (s.type != ViewType::kPerspective && s.type != ViewType::kBirdseye) {
    check(s.radius > 0 && s.radius <= kMaxViewLength_m, s, "radius", "must be in (0, 10000] m, got " + num(s.radius));
  }
  check(s.depth == Depth::kFixed || s.depth == Depth::kMeasured, s, "depth",
        "must be fixed or measured, got " + std::to_string(static_cast<int>(s.depth)));
  check(s.feather_px > 0 && s.feather_px <= kMaxViewSide, s, "feather_px",
        "must be in (0, " + std::to_string(kMaxViewSide) + "], got " + num(s.feather_px));
}

}  // namespace omniview
