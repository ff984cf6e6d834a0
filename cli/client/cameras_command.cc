// `omniview cameras`: the cameras of the daemon's sources.
#include <iostream>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"

namespace omniview::cli {
namespace {

const std::string kCamerasHelp = std::string(R"(usage: omniview cameras [--source NAME] [--details]

Lists the cameras of omniviewd's sources: model, image size, field of view (degrees,
horizontal x vertical through the image centre, as far as the lens and mask let the camera
see) and position in the robot frame.

  --source NAME   only this source's cameras
  --details       also intrinsics, distortion and the full pose (quaternion w x y z)

)") + connection_help();

std::string join(const google::protobuf::RepeatedField<double>& values) {
  std::string s;
  for (double v : values) s += (s.empty() ? "" : ", ") + fixed(v, 4);
  return "[" + s + "]";
}

}  // namespace

int cameras_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(argv, {"details"}, {"source"}, kCamerasHelp);
  if (!args) return 0;
  expect_positional(*args, 0, "");
  Connection connection(connection_options(*args));

  v1::ListCamerasRequest request;
  request.set_source(args->get("source"));
  v1::ListCamerasResponse response;
  grpc::ClientContext context;
  connection.prepare(context, true);
  connection.check(connection.stub().ListCameras(&context, request, &response), "cameras");

  if (response.cameras().empty()) {
    std::cout << "no cameras" << (request.source().empty() ? "" : " in source '" + request.source() + "'") << "\n";
    // A robot's cameras are known once it has answered: say why it has not.
    grpc::ClientContext status_context;
    connection.prepare(status_context, true);
    v1::Status status;
    if (connection.stub().GetStatus(&status_context, v1::GetStatusRequest(), &status).ok()) {
      for (const auto& s : status.sources()) {
        if (!s.connected() && (request.source().empty() || s.name() == request.source())) {
          std::cout << "source '" << s.name() << "' is not connected" << (s.message().empty() ? "" : ": " + s.message())
                    << "\n";
        }
      }
    }
    return 1;
  }
  Table table({"CAMERA", "SOURCE", "MODEL", "SIZE", "FOV (deg)", "FRAME", "POSITION (m)", "MASK"});
  for (const auto& c : response.cameras()) {
    const auto& t = c.pose().translation();
    table.add({c.name(), c.source(), c.camera_model() + "/" + c.distortion_model(),
               std::to_string(c.width()) + "x" + std::to_string(c.height()),
               fixed(c.hfov_deg(), 0) + " x " + fixed(c.vfov_deg(), 0), c.frame(),
               fixed(t.x(), 3) + " " + fixed(t.y(), 3) + " " + fixed(t.z(), 3), c.has_mask() ? "yes" : "no"});
  }
  table.print(std::cout);
  // What a source found when it checked its cameras against their calibration.
  for (const auto& c : response.cameras()) {
    if (c.calibration_check().empty()) continue;
    std::cout << (c.calibration_warning() ? "calibration off: " : "calibration check: ") << c.name() << ": "
              << c.calibration_check() << "\n";
  }
  if (args->has("details")) {
    for (const auto& c : response.cameras()) {
      const auto& p = c.pose();
      std::cout << "\n"
                << c.name() << ":\n"
                << "  intrinsics: " << join(c.intrinsics()) << "\n"
                << "  distortion_coeffs: " << join(c.distortion_coeffs()) << "\n"
                << "  T_" << c.frame() << "_camera: xyz [" << fixed(p.translation().x(), 4) << ", "
                << fixed(p.translation().y(), 4) << ", " << fixed(p.translation().z(), 4) << "], q_wxyz ["
                << fixed(p.qw(), 6) << ", " << fixed(p.qx(), 6) << ", " << fixed(p.qy(), 6) << ", " << fixed(p.qz(), 6)
                << "]\n";
    }
  }
  return 0;
}

}  // namespace omniview::cli
