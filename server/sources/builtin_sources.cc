#include "server/sources/builtin_sources.h"

#include <mutex>

#include "server/sources/images_source.h"
#include "server/sources/replay_source.h"
#include "server/sources/velodyne/velodyne_source.h"

namespace omniview {

void register_builtin_sources() {
  static std::once_flag once;
  std::call_once(once, [] {
    register_source_type("images",
                         "a fixed image per camera, delivered at rate_hz (keys: rig, rig_frame, rig_pose, "
                         "images {camera: file}, rate_hz)",
                         make_images_source);
    register_source_type("replay",
                         "plays back a recording made by `omniview record` (keys: recording, rate_hz, speed, loop; "
                         "speed multiplies the recorded timing or rate_hz)",
                         make_replay_source);
    register_source_type("velodyne",
                         "a Velodyne VLP-16 over UDP whose rotations become the clouds of the camera source it "
                         "holds (keys: cameras {type, ...}, bind, port, sender, frame, parent, pose, calibration, "
                         "returns, point_time)",
                         make_velodyne_source);
  });
}

}  // namespace omniview
