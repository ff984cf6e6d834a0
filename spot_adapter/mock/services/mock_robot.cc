#include "spot_adapter/mock/services/mock_robot.h"

#include "spot_adapter/mock/sensors/render_cache.h"

namespace omniview::spot_mock {
namespace {

LidarScan scan(const synthetic::Scene& scene, const Rig& rig) {
  return scan_scene(scene, rig.frames().lookup(kWorldFrame, kBodyFrame) * T_body_lidar());
}

std::vector<cv::Mat> camera_pictures(const MockRobotConfig& config, const Rig& rig) {
  const auto render = [&] {
    return render_pictures(make_scene(config.scene), rig, kWorldFrame, config.colour, config.supersample);
  };
  if (config.render_cache.empty()) return render();
  const RenderCache cache(config.render_cache, std::string("scene=") + to_string(config.scene) +
                                                   " colour=" + (config.colour ? "1" : "0") +
                                                   " supersample=" + std::to_string(config.supersample));
  auto pictures = cache.load();
  if (pictures && pictures->size() == rig.cameras().size()) return std::move(*pictures);
  auto rendered = render();
  cache.store(rendered);
  return rendered;
}

}  // namespace

MockRobot::MockRobot(const MockRobotConfig& config)
    : rig(mock_rig()),
      cameras(camera_pictures(config, rig), config.colour),
      depths(config.scene, rig, config.render_cache),
      lidar(scan(make_scene(config.scene), rig)),
      tokens(config.credentials, config.token_policy),
      faults(config.faults) {}

}  // namespace omniview::spot_mock
