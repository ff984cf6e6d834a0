// The synthetic world the colouring tests share: a textured room, the Spot-like rig on a
// body standing (or walking) in it, a VLP-16 on the body's back, and the ground truth of
// which camera sees which point.
#pragma once

#include <memory>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/cloud/point_cloud.h"
#include "core/rig/rig.h"
#include "core/synthetic/scene.h"

namespace omniview::test {

// A 9 x 7 x 3 m room around the origin with the bare test texture (floor at z = 0).
synthetic::Scene textured_room();

// The lidar on the body: 0.3 m above its centre, 0.1 m back (the cameras look from the
// body's sides, so the two see the world from different places and parallax shows).
Pose T_body_lidar();

// spot_like_rig() with frames "lidar" and "world" (the latter placed by T_world_body).
std::shared_ptr<Rig> rig_in_world(const Pose& T_world_body);

// Every camera's image of `scene` (one ray per pixel), grey or BGR.
std::vector<cv::Mat> render_images(const synthetic::Scene& scene, const Rig& rig, bool grey = false);

// Which cameras of `rig` see a world point (inside the image and not hidden by anything in
// `scene`): the colouring tests' ground truth. Poses are looked up once, not per point (a
// lookup and an inverse per point were most of those tests' time).
class Visibility {
 public:
  Visibility(const synthetic::Scene& scene, const Rig& rig);
  bool camera_sees(size_t camera, const Vec3& p_world) const;
  bool any_camera_sees(const Vec3& p_world) const;

 private:
  const synthetic::Scene& scene_;
  const Rig& rig_;
  std::vector<Pose> T_cam_world_;
  std::vector<Vec3> centre_world_;
};

inline double luma(const PointCloud::Rgb& rgb) { return 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2]; }

}  // namespace omniview::test
