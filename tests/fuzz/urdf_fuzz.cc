// Fuzz target: URDF text (a user's robot description) turned into a robot model, then
// forward kinematics at two poses. std::runtime_error / std::invalid_argument naming the
// problem is the expected answer to bad input; a crash, a hang, any other exception, or a
// model whose links or vertices are not finite numbers is a bug. Mesh URIs resolve against
// a folder that does not exist, so no mesh file is read.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "core/robot/model/urdf_loader.h"

namespace {

void expect_finite(const omniview::robot::RobotModel& model, double position) {
  std::vector<double> q(model.variable_names().size(), position);
  for (const auto& pose : model.link_poses(q)) {
    if (!pose.matrix().allFinite()) std::abort();
  }
  for (const auto& visual : model.visuals()) {
    for (const auto& p : visual.mesh.positions) {
      if (!p.allFinite()) std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string xml(reinterpret_cast<const char*>(data), size);
  try {
    const auto model = omniview::robot::load_urdf_string(xml, "/nonexistent-omniview-fuzz", {}, "fuzz.urdf");
    expect_finite(model, 0.0);
    expect_finite(model, 1.0);
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
