// Rendering synthetic scenes: camera images through calibrated models, and the texture a
// view's surface carries (the golden reference).
#pragma once

#include <opencv2/core/mat.hpp>

#include "core/rig/rig.h"
#include "core/synthetic/scene.h"
#include "core/view/view.h"

namespace omniview::synthetic {

struct RenderOptions {
  int supersample = 3;  // supersample x supersample rays per pixel, box-filtered
  bool grey = false;    // CV_8UC1 (luma) instead of CV_8UC3 BGR
};

// The image camera `index` of `rig` sees, with the scene given in `world_frame`. Pixels
// whose ray leaves the model, the lens' fov_deg or the mask, or hits nothing, are black.
cv::Mat render_camera(const Scene& scene, const Rig& rig, size_t index, const std::string& world_frame,
                      const RenderOptions& options = {});

// The golden reference: Scene::texture at every view pixel's surface point (CV_8UC3 BGR),
// and in `on_surface` (CV_8UC1, 255/0) where the view has a surface point at all.
// T_world_view places the view. It equals what the cameras see of a scene with default
// materials whose geometry is the view's surface (Scene::matching).
cv::Mat texture_at_view(const View& view, const Pose& T_world_view, cv::Mat* on_surface = nullptr);

}  // namespace omniview::synthetic
