#include "tests/golden/golden.h"

#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/map/apply.h"
#include "core/synthetic/render.h"
#include "core/view/view.h"

namespace omniview::golden {

Score run(const synthetic::Scene& scene, const Rig& render_rig, const Rig& map_rig, const ViewSpec& spec,
          const std::string& world_frame, bool grey_cameras, int out_channels) {
  std::vector<cv::Mat> images;
  for (size_t i = 0; i < render_rig.cameras().size(); ++i) {
    images.push_back(synthetic::render_camera(scene, render_rig, i, world_frame, {3, grey_cameras}));
  }
  const auto view = View::create(spec);
  const FusionMap map = build_map(map_rig, *view);
  Score s;
  apply_map(map, images, s.rendered, out_channels);

  const std::string frame = spec.frame.empty() ? render_rig.default_frame() : spec.frame;
  const Pose T_world_view = render_rig.frames().lookup(world_frame, frame) * spec.T_frame_view();
  cv::Mat on_surface;
  s.reference = synthetic::texture_at_view(*view, T_world_view, &on_surface);
  if (out_channels == 1) cv::cvtColor(s.reference, s.reference, cv::COLOR_BGR2GRAY);

  double squared_error = 0;
  size_t covered = 0, surface = 0;
  for (int v = 0; v < map.height; ++v) {
    for (int u = 0; u < map.width; ++u) {
      if (!on_surface.at<uint8_t>(v, u)) continue;
      ++surface;
      if (map.primary[static_cast<size_t>(v) * map.width + u].cam == kNoCamera) continue;
      ++covered;
      for (int c = 0; c < out_channels; ++c) {
        const double d = double(s.rendered.ptr<uint8_t>(v)[u * out_channels + c]) -
                         double(s.reference.ptr<uint8_t>(v)[u * out_channels + c]);
        squared_error += d * d;
      }
    }
  }
  s.coverage = surface ? double(covered) / surface : 0;
  const double mse = covered ? squared_error / (double(covered) * out_channels) : 1e9;
  s.psnr_db = 10 * std::log10(255.0 * 255.0 / std::max(mse, 1e-12));
  return s;
}

Rig example_rig() { return load_rig_yaml(OMNIVIEW_SOURCE_DIR "/config/examples/dual_fisheye/rig.yaml"); }

}  // namespace omniview::golden
