#include "spot_adapter/client/robot_channels.h"

#include <stdexcept>

#include <grpc/grpc.h>
#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/support/channel_arguments.h>

namespace omniview::spot {

RobotAddress parse_robot_address(const std::string& text) {
  if (text.find("://") != std::string::npos) {
    throw std::invalid_argument("'" + text + "': give host[:port] without a scheme (the robot speaks gRPC over TLS)");
  }
  RobotAddress a;
  std::string port;
  if (!text.empty() && text.front() == '[') {  // [IPv6]:port
    const auto close = text.find(']');
    if (close == std::string::npos) throw std::invalid_argument("'" + text + "' lacks the closing ']'");
    a.host = text.substr(1, close - 1);
    if (close + 1 < text.size()) {
      if (text[close + 1] != ':') throw std::invalid_argument("'" + text + "': expected ':PORT' after ']'");
      port = text.substr(close + 2);
    }
  } else if (const auto colon = text.rfind(':'); colon != std::string::npos && text.find(':') == colon) {
    a.host = text.substr(0, colon);
    port = text.substr(colon + 1);
  } else {
    a.host = text;  // a bare host (or an IPv6 address without brackets and port)
  }
  if (a.host.empty()) throw std::invalid_argument("'" + text + "' names no host");
  if (!port.empty()) {
    size_t used = 0;
    int p = 0;
    try {
      p = std::stoi(port, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != port.size() || p < 1 || p > 65535) {
      throw std::invalid_argument("'" + text + "': port must be a number in 1..65535");
    }
    a.port = p;
  }
  return a;
}

std::string to_string(const RobotAddress& address) {
  const bool v6 = address.host.find(':') != std::string::npos;
  return (v6 ? "[" + address.host + "]" : address.host) + ":" + std::to_string(address.port);
}

std::string full_authority(const std::string& authority) {
  return authority.find('.') == std::string::npos ? authority + ".spot.robot" : authority;
}

RobotChannels::RobotChannels(RobotAddress address, std::string ca_pem)
    : address_(std::move(address)), ca_pem_(std::move(ca_pem)) {}

std::shared_ptr<grpc::Channel> RobotChannels::channel(const std::string& authority) {
  const std::string name = full_authority(authority);
  std::lock_guard lock(mutex_);
  auto& channel = channels_[name];
  if (channel) return channel;
  grpc::SslCredentialsOptions tls;
  tls.pem_root_certs = ca_pem_;
  grpc::ChannelArguments args;
  args.SetSslTargetNameOverride(name);
  // As Spot's SDKs: large messages (several camera images), keepalive to notice a robot
  // that walked out of Wi-Fi range.
  args.SetMaxReceiveMessageSize(100 << 20);
  args.SetMaxSendMessageSize(100 << 20);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIME_MS, 5000);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 5000);
  // gRPC's default reconnect backoff grows to two minutes; views must resume within a
  // second of the robot coming back (a retry every half second costs a TCP SYN). The
  // "minimum" backoff is really the time one connection attempt may take: TCP and TLS
  // over poor Wi-Fi need seconds.
  args.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 200);
  args.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 500);
  args.SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, 5000);
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // our own connections, not shared with others
  channel = grpc::CreateCustomChannel(to_string(address_), grpc::SslCredentials(tls), args);
  return channel;
}

bool RobotChannels::any_connected() {
  std::lock_guard lock(mutex_);
  for (const auto& [name, channel] : channels_) {
    if (channel->GetState(false) == GRPC_CHANNEL_READY) return true;
  }
  return false;
}

void RobotChannels::reset() {
  std::lock_guard lock(mutex_);
  channels_.clear();
}

}  // namespace omniview::spot
