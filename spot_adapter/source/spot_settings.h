// The `spot` source's config keys:
//
//   - name: spot
//     type: spot
//     robot: 192.168.80.3            # host[:port]; port 443 when left out
//     ca_file: robot_ca.pem          # the CA the robot's certificates chain to
//     credentials_file: spot.cred    # YAML {username, password}; or leave it out and set
//                                    # BOSDYN_CLIENT_USERNAME / BOSDYN_CLIENT_PASSWORD
//     cameras: [frontleft_fisheye_image, frontright_fisheye_image, left_fisheye_image,
//               right_fisheye_image, back_fisheye_image]    # the default: the five body cameras
//     rate_hz: 15                    # image sets per second while somebody watches
//     image_format: jpeg             # jpeg | raw
//     jpeg_quality: 75
//     pixel_format: greyscale        # greyscale | rgb: what to ask for first (the other is the fallback)
//     timeout_s: 2                   # per call
//     requests_in_flight: 2          # GetImage calls that may overlap: the rate is at most
//                                    # this many image sets per round trip (Wi-Fi: 100-300 ms)
//     point_cloud_source: auto       # the lidar for coloured clouds: auto (the robot's first
//                                    # point-cloud source), none, or a source's name
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "server/source/source_registry.h"
#include "spot_adapter/client/robot_channels.h"

namespace omniview::spot {

struct SpotSettings {
  RobotAddress address;
  std::string ca_pem;
  std::string credentials_file;  // empty: the environment
  std::vector<std::string> cameras;
  double rate_hz = 15;
  bool jpeg = true;
  int jpeg_quality = 75;
  bool prefer_rgb = false;
  std::chrono::milliseconds timeout{2000};
  int requests_in_flight = 2;
  std::string point_cloud_source = "auto";  // "auto", "none" or a point-cloud source's name
};

const std::vector<std::string>& default_body_cameras();

// Throws ConfigError naming the config file, line and key. Credentials are only checked
// for presence (file readable, or the variables set); they are read at each login.
SpotSettings parse_spot_settings(const SourceConfig& config);

}  // namespace omniview::spot
