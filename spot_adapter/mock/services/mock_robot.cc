#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {
namespace {

LidarScan scan(const synthetic::Scene& scene, const Rig& rig) {
  return scan_scene(scene, rig.frames().lookup(kWorldFrame, kBodyFrame) * T_body_lidar());
}

}  // namespace

MockRobot::MockRobot(const MockRobotConfig& config)
    : rig(mock_rig()),
      cameras(make_scene(config.scene), rig, kWorldFrame, config.colour, config.supersample),
      lidar(scan(make_scene(config.scene), rig)),
      tokens(config.credentials, config.token_policy),
      faults(config.faults) {}

}  // namespace omniview::spot_mock
