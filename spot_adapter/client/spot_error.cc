#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {

void check_status(const grpc::Status& status, const std::string& what) {
  if (status.ok()) return;
  std::string detail = what + " failed: " + status.error_message() + " (gRPC code " +
                      std::to_string(static_cast<int>(status.error_code())) + ")";
  const std::string& m = status.error_message();
  if (m.find("certificate verify failed") != std::string::npos || m.find("Handshake failed") != std::string::npos ||
      m.find("handshake failed") != std::string::npos) {
    detail += "; the TLS handshake failed: does ca_file hold the CA the robot's certificates chain to?";
  }
  switch (status.error_code()) {
    case grpc::StatusCode::UNAUTHENTICATED:
      throw SpotError(SpotError::Kind::kTokenRejected, detail, status.error_code());
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
    case grpc::StatusCode::CANCELLED:
    case grpc::StatusCode::RESOURCE_EXHAUSTED:  // the robot proxy's HTTP 429
    case grpc::StatusCode::ABORTED:
      throw SpotError(SpotError::Kind::kUnreachable, detail, status.error_code());
    default:
      // UNIMPLEMENTED (HTTP 502/404 from the proxy: service not registered), INTERNAL, ...
      throw SpotError(SpotError::Kind::kProtocol, detail, status.error_code());
  }
}

}  // namespace omniview::spot
