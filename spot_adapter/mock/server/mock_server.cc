#include "spot_adapter/mock/server/mock_server.h"

#include <iostream>
#include <stdexcept>

#include <grpc/grpc.h>
#include <grpcpp/server_builder.h>

#include "spot_adapter/mock/auth/certificates.h"
#include "spot_adapter/mock/auth/credentials.h"
#include "spot_adapter/mock/server/tls_credentials.h"
#include "spot_adapter/mock/services/auth_service.h"
#include "spot_adapter/mock/services/control_service.h"
#include "spot_adapter/mock/services/directory_service.h"
#include "spot_adapter/mock/services/image_service.h"
#include "spot_adapter/mock/services/point_cloud_service.h"
#include "spot_adapter/mock/services/robot_id_service.h"
#include "spot_adapter/mock/services/time_sync_service.h"
#include "spot_adapter/mock/wire/spot_messages.h"
#include "spot_adapter/mock/services/robot_state_service.h"

namespace omniview::spot_mock {
namespace {

constexpr int kMaxMessageBytes = 100 << 20;  // what BD's SDKs allow both ways

std::string host_port(const std::string& host, int port) {
  const bool ipv6 = host.find(':') != std::string::npos && host.front() != '[';
  return (ipv6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

}  // namespace

MockServer::MockServer(const MockOptions& options) {
  if (ensure_certificates(options.certs_dir)) {
    std::cerr << "spot-mock: made a CA and certificates in " << options.certs_dir << " (clients trust "
              << ca_cert_file(options.certs_dir) << ")" << std::endl;
  }
  bool created = false;
  MockRobotConfig config = options.robot;
  config.credentials = load_or_create_credentials(options.credentials_file, &created);
  if (created) {
    std::cerr << "spot-mock: made login " << options.credentials_file << " (username " << config.credentials.username
              << ", a random password: read it there)" << std::endl;
  }
  robot_ = std::make_unique<MockRobot>(config);
  auth_ = std::make_unique<AuthService>(*robot_);
  directory_ = std::make_unique<DirectoryService>(*robot_);
  robot_id_ = std::make_unique<RobotIdService>(*robot_);
  image_ = std::make_unique<ImageService>(*robot_);
  point_cloud_ = std::make_unique<PointCloudService>(*robot_);
  robot_state_ = std::make_unique<RobotStateService>(*robot_);
  time_sync_ = std::make_unique<TimeSyncService>(*robot_);
  set_robot_clock_offset(options.clock_offset);
  control_ = std::make_unique<ControlService>(*robot_);

  grpc::ServerBuilder builder;
  int bound_port = 0;
  // gRPC lets a second server share a port (SO_REUSEPORT): two mocks would then split
  // the connections between two robots with different CAs. Refuse instead.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.AddListeningPort(host_port(options.bind, options.port), mock_server_credentials(options.certs_dir),
                           &bound_port);
  builder.SetMaxReceiveMessageSize(kMaxMessageBytes);
  builder.SetMaxSendMessageSize(kMaxMessageBytes);
  for (grpc::Service* s : std::initializer_list<grpc::Service*>{auth_.get(), directory_.get(), robot_id_.get(),
                                                                image_.get(), point_cloud_.get(), robot_state_.get(),
                                                                time_sync_.get(), control_.get()}) {
    builder.RegisterService(s);
  }
  server_ = builder.BuildAndStart();
  if (!server_ || bound_port == 0) {
    throw std::runtime_error("cannot listen on " + host_port(options.bind, options.port) +
                             " (in use, or not an address of this machine?)");
  }
  address_ = host_port(options.bind, bound_port);
}

MockServer::~MockServer() { shutdown(std::chrono::milliseconds(0)); }

void MockServer::shutdown(std::chrono::milliseconds grace) {
  if (!server_) return;
  server_->Shutdown(std::chrono::system_clock::now() + grace);
  server_->Wait();
  server_.reset();
}

}  // namespace omniview::spot_mock
