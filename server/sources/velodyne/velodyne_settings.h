// The keys of a `type: velodyne` source (see velodyne_source.h for the YAML).
#pragma once

#include <string>

#include "core/cloud/vlp16.h"
#include "core/geometry/pose.h"
#include "server/source/source_registry.h"

namespace omniview {

struct VelodyneSettings {
  std::string bind = "127.0.0.1";  // loopback unless the config names the lidar's network
  int port = 2368;                 // the VLP-16's factory data port
  std::string sender;              // empty: any; else only datagrams from this address
  std::string frame = "velodyne";  // the cloud's frame, added to the camera rig
  std::string parent;              // empty: the camera rig's default frame
  Pose T_parent_lidar = Pose::Identity();
  Vlp16Calibration calibration;
  Vlp16Returns returns = Vlp16Returns::kAll;
  bool point_time = true;  // keep each point's firing time (for motion compensation)
};

// Reads the velodyne keys of `config` (not `cameras`); throws ConfigError naming the key.
VelodyneSettings parse_velodyne_settings(const SourceConfig& config);

}  // namespace omniview
