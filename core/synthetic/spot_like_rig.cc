#include "core/synthetic/spot_like_rig.h"

#include <cmath>

namespace omniview::synthetic {
namespace {

// A pinhole mounted like a view (x = optical axis, y left, z up), angles in degrees.
Camera mounted_pinhole(const std::string& name, const Vec3& xyz, double yaw_deg, double pitch_deg, double roll_deg) {
  Camera c;
  c.name = name;
  c.model = CameraModel(PinholeRadtan(330, 330, 319.5, 239.5));
  c.width = 640;
  c.height = 480;
  const double d = M_PI / 180;
  c.T_parent_cam = make_pose(xyz, yaw_deg * d, pitch_deg * d, roll_deg * d);
  c.T_parent_cam.linear() = c.T_parent_cam.linear() * R_view_optical();
  return c;
}

}  // namespace

Rig spot_like_rig() {
  Rig rig("body");
  rig.add_camera(mounted_pinhole("frontleft", Vec3(0.42, 0.04, 0.02), -35, 25, 78));
  rig.add_camera(mounted_pinhole("frontright", Vec3(0.42, -0.04, 0.02), 35, 25, 102 - 180));
  rig.add_camera(mounted_pinhole("left", Vec3(-0.05, 0.11, 0.03), 90, 30, 0));
  rig.add_camera(mounted_pinhole("right", Vec3(-0.05, -0.11, 0.03), -90, 30, 180));
  rig.add_camera(mounted_pinhole("back", Vec3(-0.43, 0, 0.03), 180, 30, 0));
  return rig;
}

}  // namespace omniview::synthetic
