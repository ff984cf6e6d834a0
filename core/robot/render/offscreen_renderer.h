// Software offscreen rendering of triangle meshes with OSMesa (Mesa's llvmpipe: no display,
// no GPU), from exactly a pinhole camera's point of view.
//
// Shading: a headlight (a directional light along the viewing axis), Lambert on both faces,
// plus ambient, so surfaces facing the camera are brightest and edges between faces stay
// readable. The depth test resolves occlusion; nothing is culled.
//
// Output: BGRA, CV_8UC4 in OpenCV channel order, NOT premultiplied. Alpha is the material's
// alpha where the robot is (255 for opaque materials) and 0 elsewhere; translucent parts
// are not sorted.
//
// Threads: OSMesa binds a context to the calling thread and Mesa's GL state is not
// thread-safe, so every render holds one process-wide lock from MakeCurrent to release.
// Renderers may be used from any thread; renders run one at a time.
#pragma once

#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "core/robot/model/triangle_mesh.h"
#include "core/robot/render/pinhole_camera.h"

namespace omniview::robot {

struct DrawItem {
  const TriangleMesh* mesh = nullptr;
  Pose T_robot_mesh = Pose::Identity();  // mesh coordinates -> robot base frame
};

class OffscreenRenderer {
 public:
  // Throws std::runtime_error when OSMesa cannot create a context.
  OffscreenRenderer();
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  // Renders `items` seen from the camera whose optical frame has pose T_robot_camera in the
  // robot's base frame. Returns a camera.width x camera.height BGRA image (see above).
  cv::Mat render(const std::vector<DrawItem>& items, const PinholeCamera& camera, const Pose& T_robot_camera);

 private:
  struct Context;
  std::unique_ptr<Context> context_;
};

}  // namespace omniview::robot
