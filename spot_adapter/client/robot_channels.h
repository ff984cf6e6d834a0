// gRPC channels to one robot: one per authority, all to the same address, as Spot's own
// SDKs do. The robot's proxy routes on the :authority header, which gRPC takes from the
// TLS target-name override, and every certificate is issued for its authority.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <grpcpp/channel.h>

namespace omniview::spot {

struct RobotAddress {
  std::string host;
  int port = 443;
};

// "192.168.80.3", "spot.local:443", "[fe80::1]:443". Throws std::invalid_argument.
RobotAddress parse_robot_address(const std::string& text);
std::string to_string(const RobotAddress& address);

// "image" -> "image.spot.robot"; a name with a dot is kept as it is.
std::string full_authority(const std::string& authority);

class RobotChannels {
 public:
  // `ca_pem`: the certificate(s) the robot's chain ends in (Boston Dynamics' root CA, or
  // the one spot-mock generates).
  RobotChannels(RobotAddress address, std::string ca_pem);

  // The channel for `authority` (created on first use, then kept).
  std::shared_ptr<grpc::Channel> channel(const std::string& authority);
  // Drops every channel, so the next calls connect afresh (after the robot went away).
  void reset();
  // Some connection to the robot is up now (a call that failed on it was answered by the
  // robot, not lost on the way).
  bool any_connected();

  const RobotAddress& address() const { return address_; }

 private:
  RobotAddress address_;
  std::string ca_pem_;
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<grpc::Channel>> channels_;
};

}  // namespace omniview::spot
