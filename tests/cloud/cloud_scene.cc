#include "cloud_scene.h"

#include "core/synthetic/render.h"
#include "core/synthetic/spot_like_rig.h"

namespace omniview::test {

synthetic::Scene textured_room() {
  synthetic::Scene scene;
  scene.add(synthetic::Box{Vec3(-4.5, -3.5, 0), Vec3(4.5, 3.5, 3)});
  return scene;
}

Pose T_body_lidar() { return make_pose(Vec3(-0.1, 0, 0.3), 0, 0, 0); }

std::shared_ptr<Rig> rig_in_world(const Pose& T_world_body) {
  auto rig = std::make_shared<Rig>(synthetic::spot_like_rig());
  rig->add_frame("lidar", "body", T_body_lidar());
  rig->add_frame("world", "body", T_world_body.inverse());
  return rig;
}

std::vector<cv::Mat> render_images(const synthetic::Scene& scene, const Rig& rig, bool grey) {
  std::vector<cv::Mat> images;
  synthetic::RenderOptions options;
  options.supersample = 1;
  options.grey = grey;
  for (size_t i = 0; i < rig.cameras().size(); ++i) images.push_back(synthetic::render_camera(scene, rig, i, "world", options));
  return images;
}

bool camera_sees(const synthetic::Scene& scene, const Rig& rig, size_t index, const Vec3& p_world) {
  const Camera& cam = rig.cameras()[index];
  const Pose T_world_cam = rig.camera_pose("world", index);
  const Vec3 p_cam = T_world_cam.inverse() * p_world;
  Vec2 uv;
  if (!project(cam.model, p_cam, uv) || !cam.in_image(uv.x(), uv.y())) return false;
  const Vec3 origin = T_world_cam.translation();
  const Vec3 dir = p_world - origin;
  const auto hit = scene.intersect(origin, dir);
  return hit && hit->t > 1 - 1e-3;  // dir spans the whole way: t = 1 at the point
}

}  // namespace omniview::test
