// spot-mock's gRPC server: one port, TLS, every bosdyn.api service plus the control service.
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include <grpcpp/server.h>

#include "spot_adapter/mock/server/mock_options.h"

namespace omniview::spot_mock {

class AuthService;
class DirectoryService;
class RobotIdService;
class ImageService;
class PointCloudService;
class RobotStateService;
class TimeSyncService;
class ControlService;

class MockServer {
 public:
  // Makes the certificates and credentials file if missing (saying so on stderr), renders the
  // scene and starts serving. Throws std::runtime_error if any of that fails.
  explicit MockServer(const MockOptions& options);
  ~MockServer();

  const std::string& address() const { return address_; }  // HOST:PORT actually bound

  // Stops taking calls; calls still running after `grace` are cancelled.
  void shutdown(std::chrono::milliseconds grace);

 private:
  std::unique_ptr<MockRobot> robot_;
  std::unique_ptr<AuthService> auth_;
  std::unique_ptr<DirectoryService> directory_;
  std::unique_ptr<RobotIdService> robot_id_;
  std::unique_ptr<ImageService> image_;
  std::unique_ptr<PointCloudService> point_cloud_;
  std::unique_ptr<RobotStateService> robot_state_;
  std::unique_ptr<TimeSyncService> time_sync_;
  std::unique_ptr<ControlService> control_;
  std::unique_ptr<grpc::Server> server_;
  std::string address_;
};

}  // namespace omniview::spot_mock
