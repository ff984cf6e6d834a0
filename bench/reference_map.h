// The anchor for map builds: the paper's method (Oehler & von Stryk, ECMR 2021, Sec. III)
// restated the straightforward way, per output pixel: the surface point in double
// precision through the view's virtual interface, transformed into every camera,
// projected with that camera's model, and the camera whose pixel is nearest its image
// centre kept. What the map builder does, without batching, vectorising or reuse.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/rig/rig.h"
#include "core/view/view.h"

namespace omniview::bench {

struct ReferenceEntry {
  float u, v;
  int cam;  // -1: no camera
};

inline std::vector<ReferenceEntry> reference_map(const Rig& rig, const View& view) {
  const auto& cams = rig.cameras();
  const std::string frame = view.spec().frame.empty() ? rig.default_frame() : view.spec().frame;
  std::vector<Pose> T_cam_view;
  for (size_t i = 0; i < cams.size(); ++i) T_cam_view.push_back(rig.camera_pose(frame, i).inverse() * view.spec().T_frame_view());
  std::vector<ReferenceEntry> map(static_cast<size_t>(view.width()) * view.height(), ReferenceEntry{0, 0, -1});
  for (int v = 0; v < view.height(); ++v) {
    for (int u = 0; u < view.width(); ++u) {
      Vec3 p;
      if (!view.pixel_to_point(u, v, p)) continue;
      double best = std::numeric_limits<double>::infinity();
      ReferenceEntry& e = map[static_cast<size_t>(v) * view.width() + u];
      for (size_t i = 0; i < cams.size(); ++i) {
        const Vec3 pc = T_cam_view[i] * p;
        if (cams[i].fov_deg > 0 && std::acos(pc.z() / pc.norm()) > cams[i].fov_deg * M_PI / 360) continue;
        Eigen::Vector2d uv;
        if (!project(cams[i].model, pc, uv) || !cams[i].in_image(uv.x(), uv.y())) continue;
        const double du = (uv.x() - (cams[i].width - 1) / 2.0) / cams[i].width;
        const double dv = (uv.y() - (cams[i].height - 1) / 2.0) / cams[i].height;
        if (du * du + dv * dv < best) {
          best = du * du + dv * dv;
          e = ReferenceEntry{static_cast<float>(uv.x()), static_cast<float>(uv.y()), static_cast<int>(i)};
        }
      }
    }
  }
  return map;
}

}  // namespace omniview::bench
