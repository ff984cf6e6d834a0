#include "server/convert/convert.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/camera/camera_model.h"
#include "core/view/view_keys.h"
#include "core/view/pinhole_view.h"

namespace omniview {

v1::Vec3 to_proto(const Vec3& v) {
  v1::Vec3 out;
  out.set_x(v.x());
  out.set_y(v.y());
  out.set_z(v.z());
  return out;
}

Vec3 from_proto(const v1::Vec3& v) { return Vec3(v.x(), v.y(), v.z()); }

v1::Transform to_proto(const Pose& pose) {
  v1::Transform t;
  *t.mutable_translation() = to_proto(Vec3(pose.translation()));
  const Eigen::Quaterniond q(pose.rotation());
  t.set_qw(q.w());
  t.set_qx(q.x());
  t.set_qy(q.y());
  t.set_qz(q.z());
  return t;
}

Pose from_proto(const v1::Transform& t) {
  Eigen::Quaterniond q(t.qw(), t.qx(), t.qy(), t.qz());
  if (q.norm() < 1e-9) q = Eigen::Quaterniond::Identity();  // unset message
  Pose pose = Pose::Identity();
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = from_proto(t.translation());
  return pose;
}

v1::ViewType to_proto(ViewType type) {
  switch (type) {
    case ViewType::kPerspective: return v1::PERSPECTIVE;
    case ViewType::kBirdseye: return v1::BIRDSEYE;
    case ViewType::kCylindrical: return v1::CYLINDRICAL;
    case ViewType::kMercator: return v1::MERCATOR;
    case ViewType::kEquirectangular: return v1::EQUIRECTANGULAR;
    case ViewType::kFisheye: return v1::FISHEYE;
  }
  return v1::VIEW_TYPE_UNSPECIFIED;
}

ViewType from_proto(v1::ViewType type, const std::string& what) {
  switch (type) {
    case v1::PERSPECTIVE: return ViewType::kPerspective;
    case v1::BIRDSEYE: return ViewType::kBirdseye;
    case v1::CYLINDRICAL: return ViewType::kCylindrical;
    case v1::MERCATOR: return ViewType::kMercator;
    case v1::EQUIRECTANGULAR: return ViewType::kEquirectangular;
    case v1::FISHEYE: return ViewType::kFisheye;
    default: break;
  }
  throw std::invalid_argument(what + ": view type missing or unknown (" + std::to_string(type) +
                              "); one of PERSPECTIVE, BIRDSEYE, CYLINDRICAL, MERCATOR, EQUIRECTANGULAR, FISHEYE");
}

v1::Fusion to_proto(Fusion fusion) {
  return fusion == Fusion::kBlend ? v1::BLEND : v1::NEAREST_CENTRE;
}

Fusion from_proto(v1::Fusion fusion, const std::string& what) {
  switch (fusion) {
    case v1::NEAREST_CENTRE: return Fusion::kNearestCentre;
    case v1::BLEND: return Fusion::kBlend;
    default: break;
  }
  throw std::invalid_argument(what + ": fusion missing or unknown (" + std::to_string(fusion) +
                              "); one of NEAREST_CENTRE, BLEND");
}

v1::Depth to_proto(Depth depth) { return depth == Depth::kMeasured ? v1::MEASURED : v1::FIXED; }

Depth from_proto(v1::Depth depth, const std::string& what) {
  switch (depth) {
    case v1::FIXED: return Depth::kFixed;
    case v1::MEASURED: return Depth::kMeasured;
    default: break;
  }
  throw std::invalid_argument(what + ": depth unknown (" + std::to_string(depth) + "); one of FIXED, MEASURED");
}

v1::ViewSpec to_proto(const ViewSpec& s) {
  v1::ViewSpec p;
  p.set_name(s.name);
  p.set_type(to_proto(s.type));
  p.set_source(s.source);
  p.set_width(s.width);
  p.set_height(s.height);
  p.set_frame(s.frame);
  *p.mutable_position() = to_proto(s.position);
  p.set_yaw_deg(s.yaw_deg);
  p.set_pitch_deg(s.pitch_deg);
  p.set_roll_deg(s.roll_deg);
  p.set_hfov_deg(s.hfov_deg);
  p.set_distance(s.distance);
  p.set_height_m(s.height_m);
  p.set_ground_z(s.ground_z);
  p.set_radius(s.radius);
  p.set_vfov_deg(s.vfov_deg);
  p.set_azimuth_span_deg(s.azimuth_span_deg);
  p.set_lat_min_deg(s.lat_min_deg);
  p.set_lat_max_deg(s.lat_max_deg);
  p.set_fov_deg(s.fov_deg);
  p.set_fusion(to_proto(s.fusion));
  p.set_feather_px(s.feather_px);
  p.set_overlay(s.overlay);
  p.set_gain_compensation(s.gain_compensation);
  p.set_ground(s.ground);
  p.set_overlay_opacity(s.overlay_opacity);
  p.set_depth(to_proto(s.depth));
  return p;
}

namespace {

// A surface key of another type would change nothing visible: refuse it, naming key and
// type. A key that keeps its value passes, so that a full spec (GetView's, changed and sent
// back) is accepted as it stands.
void reject_inapplicable_changes(const v1::ViewSpec& patch, const ViewSpec& before, const ViewSpec& after) {
  const auto* descriptor = patch.GetDescriptor();
  const auto* reflection = patch.GetReflection();
  const v1::ViewSpec old_values = to_proto(before);
  for (const auto& key : surface_keys()) {
    const auto* field = descriptor->FindFieldByName(key);
    if (!field || !reflection->HasField(patch, field)) continue;
    if (reflection->GetDouble(patch, field) == reflection->GetDouble(old_values, field)) continue;
    if (const auto why = inapplicable_key(key, after.type); !why.empty()) {
      throw std::invalid_argument("view '" + after.name + "': " + why);
    }
  }
}

}  // namespace

ViewSpec spec_from_proto(const v1::ViewSpec& request) {
  if (!request.has_type()) {
    throw std::invalid_argument("view '" + request.name() +
                                "': type is required (PERSPECTIVE, BIRDSEYE, CYLINDRICAL, MERCATOR, "
                                "EQUIRECTANGULAR or FISHEYE)");
  }
  ViewSpec spec = default_view_spec(from_proto(request.type(), "view '" + request.name() + "'"));
  apply_patch(request, spec);
  return spec;
}

void apply_patch(const v1::ViewSpec& p, ViewSpec& s) {
  const ViewSpec before = s;
  const std::string what = "view '" + (p.has_name() ? p.name() : s.name) + "'";
  if (p.has_name()) s.name = p.name();
  if (p.has_type()) s.type = from_proto(p.type(), what);
  if (p.has_source()) s.source = p.source();
  if (p.has_width()) s.width = p.width();
  if (p.has_height()) s.height = p.height();
  if (p.has_frame()) s.frame = p.frame();
  if (p.has_position()) s.position = from_proto(p.position());
  const std::pair<bool (v1::ViewSpec::*)() const, std::pair<double (v1::ViewSpec::*)() const, double*>> numbers[] = {
      {&v1::ViewSpec::has_yaw_deg, {&v1::ViewSpec::yaw_deg, &s.yaw_deg}},
      {&v1::ViewSpec::has_pitch_deg, {&v1::ViewSpec::pitch_deg, &s.pitch_deg}},
      {&v1::ViewSpec::has_roll_deg, {&v1::ViewSpec::roll_deg, &s.roll_deg}},
      {&v1::ViewSpec::has_hfov_deg, {&v1::ViewSpec::hfov_deg, &s.hfov_deg}},
      {&v1::ViewSpec::has_distance, {&v1::ViewSpec::distance, &s.distance}},
      {&v1::ViewSpec::has_height_m, {&v1::ViewSpec::height_m, &s.height_m}},
      {&v1::ViewSpec::has_ground_z, {&v1::ViewSpec::ground_z, &s.ground_z}},
      {&v1::ViewSpec::has_radius, {&v1::ViewSpec::radius, &s.radius}},
      {&v1::ViewSpec::has_vfov_deg, {&v1::ViewSpec::vfov_deg, &s.vfov_deg}},
      {&v1::ViewSpec::has_azimuth_span_deg, {&v1::ViewSpec::azimuth_span_deg, &s.azimuth_span_deg}},
      {&v1::ViewSpec::has_lat_min_deg, {&v1::ViewSpec::lat_min_deg, &s.lat_min_deg}},
      {&v1::ViewSpec::has_lat_max_deg, {&v1::ViewSpec::lat_max_deg, &s.lat_max_deg}},
      {&v1::ViewSpec::has_fov_deg, {&v1::ViewSpec::fov_deg, &s.fov_deg}},
      {&v1::ViewSpec::has_feather_px, {&v1::ViewSpec::feather_px, &s.feather_px}},
      {&v1::ViewSpec::has_overlay_opacity, {&v1::ViewSpec::overlay_opacity, &s.overlay_opacity}},
  };
  for (const auto& [has, get_and_field] : numbers) {
    if ((p.*has)()) *get_and_field.second = (p.*(get_and_field.first))();
  }
  if (p.has_fusion()) s.fusion = from_proto(p.fusion(), what);
  if (p.has_overlay()) s.overlay = p.overlay();
  if (p.has_gain_compensation()) s.gain_compensation = p.gain_compensation();
  if (p.has_ground()) s.ground = p.ground();
  if (p.has_depth()) s.depth = from_proto(p.depth(), what);
  reject_inapplicable_changes(p, before, s);
}

double hfov_from_zoom(double zoom) { return 2 * std::atan(1.0 / zoom) * 180 / M_PI; }
double zoom_from_hfov(double hfov_deg) { return 1.0 / std::tan(hfov_deg * M_PI / 360); }

void apply_delta(const v1::ViewDelta& d, ViewSpec& s) {
  // A joystick step is a few degrees; one larger than a turn is a client's mistake that
  // wrapping would hide (a step of 1e308 would land on an arbitrary angle).
  const std::pair<double, const char*> steps[] = {
      {d.yaw_deg(), "delta.yaw_deg"}, {d.pitch_deg(), "delta.pitch_deg"}, {d.roll_deg(), "delta.roll_deg"}};
  for (const auto& [step, field] : steps) {
    if (!(std::abs(step) <= 360)) {
      throw std::invalid_argument(std::string(field) + " must be a step within +-360 degrees, got " +
                                  std::to_string(step));
    }
  }
  s.yaw_deg += d.yaw_deg();
  s.pitch_deg += d.pitch_deg();
  s.roll_deg += d.roll_deg();
  // Keep pan in (-180, 180] so repeated joystick steps do not grow without bound, and stop
  // tilt at straight down or up (a joystick held down must not flip the view over).
  // Only a step wraps: a yaw of 1e300 set outright is refused by validate(), not folded.
  if (d.yaw_deg() != 0) s.yaw_deg = std::remainder(s.yaw_deg, 360.0);
  if (d.roll_deg() != 0) s.roll_deg = std::remainder(s.roll_deg, 360.0);
  if (d.pitch_deg() != 0) s.pitch_deg = std::clamp(s.pitch_deg, -90.0, 90.0);
  const double zoom = d.zoom();
  if (zoom == 0 || zoom == 1) return;
  if (!(zoom > 0) || !std::isfinite(zoom)) {
    throw std::invalid_argument("delta.zoom must be > 0, got " + std::to_string(zoom));
  }
  switch (s.type) {
    case ViewType::kPerspective:
    case ViewType::kBirdseye:
      s.hfov_deg = hfov_from_zoom(zoom_from_hfov(s.hfov_deg) * zoom);
      break;
    case ViewType::kFisheye:
      s.fov_deg /= zoom;
      break;
    default:
      throw std::invalid_argument("view '" + s.name + "': zoom applies to perspective, birdseye and fisheye views, not " +
                                  to_string(s.type) + " (narrow a panorama with azimuth_span_deg instead)");
  }
}

std::vector<double> pinhole_intrinsics(const View& view) {
  const auto* pinhole = dynamic_cast<const PinholeView*>(&view);
  if (!pinhole) return {};
  return {pinhole->focal(), pinhole->focal(), pinhole->cx(), pinhole->cy()};
}

namespace {

// What a camera images along the row (`horizontal`) or column through its optical axis'
// pixel: the off-axis angles of the outermost usable pixels on each
// side, added, so a 210 deg fisheye whose circle fits the image says 210. Usable: the model
// has a ray there, within the lens' fov_deg, inside the mask.
double imaged_angle_deg(const Camera& c, bool horizontal) {
  // Along the lines through the optical axis' pixel: the image centre for most cameras,
  // but a lens that is one half of a shared frame (the Insta360 Air's) sits off it.
  double cu = (c.width - 1) / 2.0, cv = (c.height - 1) / 2.0;
  if (Eigen::Vector2d axis; project(c.model, Eigen::Vector3d(0, 0, 1), axis) && axis.x() >= 0 && axis.y() >= 0 &&
                            axis.x() <= c.width - 1 && axis.y() <= c.height - 1) {
    cu = axis.x(), cv = axis.y();
  }
  const double limit = c.fov_deg > 0 ? c.fov_deg / 2 * M_PI / 180 : M_PI;
  const int n = horizontal ? c.width : c.height;
  double before = 0, after = 0;  // the largest off-axis angle left/above and right/below of the centre
  for (int i = 0; i < n; ++i) {
    const double u = horizontal ? i : cu, v = horizontal ? cv : i;
    Eigen::Vector3d ray;
    if (!unproject(c.model, Eigen::Vector2d(u, v), ray)) continue;
    if (!c.mask.empty() && c.mask.at<uint8_t>(static_cast<int>(std::lround(v)), static_cast<int>(std::lround(u))) <= 127) {
      continue;
    }
    const double theta = std::atan2(std::hypot(ray.x(), ray.y()), ray.z());
    if (!(theta <= limit)) continue;
    double& side = (horizontal ? u < cu : v < cv) ? before : after;
    side = std::max(side, theta);
  }
  return (before + after) * 180 / M_PI;
}

}  // namespace

v1::Camera to_proto(const Camera& c, const Rig& rig, const std::string& source) {
  v1::Camera p;
  p.set_name(c.name);
  p.set_source(source);
  const ModelSpec m = describe(c.model);
  p.set_camera_model(m.camera_model);
  p.set_distortion_model(m.distortion_model);
  for (double v : m.intrinsics) p.add_intrinsics(v);
  for (double v : m.distortion) p.add_distortion_coeffs(v);
  p.set_width(c.width);
  p.set_height(c.height);
  p.set_fov_deg(c.fov_deg);
  p.set_has_mask(!c.mask.empty());
  p.set_hfov_deg(imaged_angle_deg(c, true));
  p.set_vfov_deg(imaged_angle_deg(c, false));
  p.set_frame(rig.default_frame());
  const auto& cams = rig.cameras();
  for (size_t i = 0; i < cams.size(); ++i) {
    if (cams[i].name == c.name) *p.mutable_pose() = to_proto(rig.camera_pose(rig.default_frame(), i));
  }
  return p;
}

}  // namespace omniview
