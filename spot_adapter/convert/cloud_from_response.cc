#include "spot_adapter/convert/cloud_from_response.h"

#include <cstring>
#include <map>

#include "spot_adapter/client/spot_error.h"
#include "spot_adapter/convert/frame_tree.h"

namespace omniview::spot {

namespace api = bosdyn::api;

namespace {

constexpr size_t kXyzBytes = 12;

// T_root_frame through the snapshot's edges, and the root's name.
Pose pose_in_root(const std::vector<FrameEdge>& edges, const std::string& frame, std::string& root,
                  const std::string& what) {
  std::map<std::string, const FrameEdge*> by_child;
  for (const auto& e : edges) by_child[e.child] = &e;
  Pose T = Pose::Identity();
  std::string at = frame;
  for (size_t steps = 0; steps <= edges.size(); ++steps) {
    const auto it = by_child.find(at);
    if (it == by_child.end()) {
      if (at == frame && edges.size() > 0) {
        // Not a child: it must be a root some edge hangs from, or it is not in the tree.
        bool is_parent = false;
        for (const auto& e : edges) is_parent = is_parent || e.parent == frame;
        if (!is_parent) throw SpotError(SpotError::Kind::kProtocol, what + ": the cloud's frame '" + frame +
                                                                        "' is not in its transforms_snapshot");
      }
      root = at;
      return T;
    }
    T = it->second->T_parent_child * T;
    at = it->second->parent;
  }
  throw SpotError(SpotError::Kind::kProtocol, what + ": the transforms_snapshot has a cycle above '" + frame + "'");
}

}  // namespace

std::chrono::system_clock::time_point cloud_acquisition_time(const api::PointCloud& cloud) {
  const auto& t = cloud.source().acquisition_time();
  return std::chrono::system_clock::time_point(std::chrono::duration_cast<std::chrono::system_clock::duration>(
      std::chrono::seconds(t.seconds()) + std::chrono::nanoseconds(t.nanos())));
}

PointCloud cloud_from_spot(const api::PointCloud& cloud, std::chrono::system_clock::time_point stamp,
                           const std::string& what) {
  if (cloud.encoding() != api::PointCloud::ENCODING_XYZ_32F) {
    throw SpotError(SpotError::Kind::kProtocol,
                    what + ": encoding " + std::to_string(cloud.encoding()) + " is not XYZ_32F, the one omniview reads");
  }
  const int stride = cloud.encoding_parameters().bytes_per_point();
  if (stride != 0 && stride != static_cast<int>(kXyzBytes)) {
    throw SpotError(SpotError::Kind::kProtocol,
                    what + ": bytes_per_point is " + std::to_string(stride) + ", XYZ_32F has 12");
  }
  if (cloud.num_points() < 0 || cloud.data().size() != static_cast<size_t>(cloud.num_points()) * kXyzBytes) {
    throw SpotError(SpotError::Kind::kProtocol, what + ": " + std::to_string(cloud.data().size()) +
                                                    " bytes of data for num_points " +
                                                    std::to_string(cloud.num_points()) + " (12 bytes a point)");
  }
  const std::string& sensor = cloud.source().frame_name_sensor();
  if (sensor.empty()) throw SpotError(SpotError::Kind::kProtocol, what + ": the source names no frame_name_sensor");
  std::string root;
  const Pose T_root_sensor =
      pose_in_root(frame_edges(cloud.source().transforms_snapshot(), what), sensor, root, what);
  const Eigen::Isometry3f T = T_root_sensor.cast<float>();

  PointCloud out;
  out.frame = root;
  out.stamp = stamp;
  out.points.resize(static_cast<size_t>(cloud.num_points()));
  const char* data = cloud.data().data();
  for (size_t i = 0; i < out.points.size(); ++i) {
    float xyz[3];
    std::memcpy(xyz, data + i * kXyzBytes, kXyzBytes);  // little-endian float32, as this host
    out.points[i] = T * Eigen::Vector3f(xyz[0], xyz[1], xyz[2]);
  }
  return out;
}

}  // namespace omniview::spot
