#include "cli/render_cloud.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "core/cloud/cloud_file.h"
#include "core/depth/column_completion.h"

namespace omniview::cli {

RenderCloud load_render_cloud(const Args& args, const Rig& rig) {
  RenderCloud out;
  out.file = args.get("cloud");
  const std::string what = "--cloud " + out.file;
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(out.file, ec);
  if (ec) throw std::runtime_error(what + ": cannot read it (" + ec.message() + ")");
  if (bytes > kMaxCloudFileBytes) {
    throw std::runtime_error(what + ": " + std::to_string(bytes) + " bytes, more than the limit of " +
                             std::to_string(kMaxCloudFileBytes) + " (2 GiB)");
  }
  PointCloud cloud;
  try {
    cloud = load_cloud(out.file, kMaxCloudPoints);  // refused by its header, before its body is parsed
  } catch (const std::exception& e) {
    // The readers name the file already: said as every other --cloud error is.
    const std::string message = e.what();
    throw std::runtime_error(message.rfind(out.file, 0) == 0 ? "--cloud " + message : what + ": " + message);
  }
  if (cloud.empty()) throw std::runtime_error(what + ": the cloud has no points");
  if (cloud.size() > kMaxCloudPoints) {
    throw std::runtime_error(what + ": " + std::to_string(cloud.size()) + " points, more than the limit of " +
                             std::to_string(kMaxCloudPoints));
  }
  out.frame = args.has("cloud-frame") ? args.get("cloud-frame") : cloud.frame.empty() ? rig.default_frame() : cloud.frame;
  const std::vector<std::string> known = rig.known_frames();
  if (std::find(known.begin(), known.end(), out.frame) == known.end()) {
    throw std::runtime_error(what + ": its frame '" + out.frame + "' (" +
                             (args.has("cloud-frame") ? "--cloud-frame" : "recorded in the file") +
                             ") is not a frame of the rig (known frames: " + joined(known) + ")");
  }
  out.non_finite = static_cast<size_t>(
      std::count_if(cloud.points.begin(), cloud.points.end(), [](const Eigen::Vector3f& p) { return !p.allFinite(); }));
  if (out.non_finite == cloud.points.size()) {
    throw std::runtime_error(what + ": none of its " + std::to_string(cloud.points.size()) +
                             " points is finite (all NaN or infinite)");
  }
  // In the robot frame, completed as the daemon completes its geometry (column_completion.h):
  // a lidar's top ring told in its own frame, and its rays from its place.
  const auto lidar = lidar_origin(rig, out.frame);
  const std::vector<uint8_t> flags = lidar ? lidar_flags(cloud.points) : std::vector<uint8_t>{};
  const Eigen::Isometry3f T_robot_cloud = rig.frames().lookup(rig.default_frame(), out.frame).cast<float>();
  out.points.reserve(cloud.points.size());
  for (const auto& p : cloud.points) out.points.push_back(T_robot_cloud * p);
  out.completion = complete_columns(rig, out.points, flags, lidar);
  return out;
}

}  // namespace omniview::cli
