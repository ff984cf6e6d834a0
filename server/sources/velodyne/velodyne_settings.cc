#include "server/sources/velodyne/velodyne_settings.h"

#include <cmath>

namespace omniview {

VelodyneSettings parse_velodyne_settings(const SourceConfig& config) {
  const YamlReader& r = *config.reader;
  const YAML::Node& n = config.node;
  const std::string& at = config.path;
  VelodyneSettings s;
  if (n["bind"]) s.bind = r.text(n["bind"], at + ".bind");
  if (n["port"]) {
    s.port = r.integer(n["port"], at + ".port");
    if (s.port < 0 || s.port > 65535) r.fail(n["port"], at + ".port", "must be 0..65535 (0: a free port)");
  }
  if (n["sender"]) s.sender = r.text(n["sender"], at + ".sender");
  if (n["frame"]) s.frame = r.text(n["frame"], at + ".frame");
  if (s.frame.empty()) r.fail(n["frame"], at + ".frame", "is empty");
  if (n["parent"]) s.parent = r.text(n["parent"], at + ".parent");
  if (const YAML::Node p = n["pose"]) {
    // As rig_pose: [x, y, z, yaw, pitch, roll] (m, deg), or any pose the reader accepts.
    if (p.IsSequence() && p.size() == 6) {
      const auto v = r.numbers(p, at + ".pose", 6);
      s.T_parent_lidar = make_pose(Vec3(v[0], v[1], v[2]), v[3] * M_PI / 180, v[4] * M_PI / 180, v[5] * M_PI / 180);
    } else {
      s.T_parent_lidar = r.pose(p, at + ".pose");
    }
  }
  if (const YAML::Node c = n["calibration"]) {
    const std::string key = at + ".calibration";
    if (!c.IsMap()) r.fail(c, key, "expected a map {elevation_deg: [16 angles], min_range_m, max_range_m}");
    r.expect_keys(c, key, {"elevation_deg", "min_range_m", "max_range_m"});
    if (c["elevation_deg"]) {
      const auto v = r.numbers(c["elevation_deg"], key + ".elevation_deg", 16);
      for (size_t i = 0; i < 16; ++i) {
        if (!(std::abs(v[i]) < 90))
          r.fail(c["elevation_deg"], key + ".elevation_deg", "angles must lie in (-90, 90) deg");
        s.calibration.elevation_deg[i] = v[i];
      }
    }
    if (c["min_range_m"]) s.calibration.min_range_m = r.number(c["min_range_m"], key + ".min_range_m");
    if (c["max_range_m"]) s.calibration.max_range_m = r.number(c["max_range_m"], key + ".max_range_m");
    if (!(s.calibration.min_range_m >= 0 && s.calibration.max_range_m > s.calibration.min_range_m &&
          std::isfinite(s.calibration.max_range_m))) {
      r.fail(c, key, "needs 0 <= min_range_m < max_range_m (finite)");
    }
  }
  if (const YAML::Node ret = n["returns"]) {
    const std::string v = r.text(ret, at + ".returns");
    if (v == "all")
      s.returns = Vlp16Returns::kAll;
    else if (v == "strongest")
      s.returns = Vlp16Returns::kStrongest;
    else if (v == "last")
      s.returns = Vlp16Returns::kLast;
    else
      r.fail(ret, at + ".returns",
             "'" + v + "': expected all, strongest or last (which returns of dual-return packets)");
  }
  if (n["point_time"]) s.point_time = r.boolean(n["point_time"], at + ".point_time");
  return s;
}

}  // namespace omniview
