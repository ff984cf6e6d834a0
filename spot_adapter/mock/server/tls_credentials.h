// The listening port's TLS: every authority's key and certificate from a folder made by
// ensure_certificates(). gRPC picks the pair whose name matches the client's SNI (its
// target-name override), as the robot's proxy presents one certificate per authority.
#pragma once

#include <memory>
#include <string>

#include <grpcpp/security/server_credentials.h>

namespace omniview::spot_mock {

// Throws std::runtime_error naming a file that cannot be read.
std::shared_ptr<grpc::ServerCredentials> mock_server_credentials(const std::string& certs_dir);

}  // namespace omniview::spot_mock
