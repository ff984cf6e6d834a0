// An error the API reports as a gRPC status: the code tells a program what happened, the
// message tells a person what to do about it.
#pragma once

#include <stdexcept>
#include <string>

#include <grpcpp/support/status_code_enum.h>

namespace omniview {

struct ApiError : std::runtime_error {
  ApiError(grpc::StatusCode code, const std::string& message) : std::runtime_error(message), code(code) {}
  grpc::StatusCode code;
};

// The HTTP status that says the same as `code` (the web port's plain HTTP routes: WHEP), as
// gRPC's own HTTP mapping does (grpc/doc/http-grpc-status-mapping, read the other way).
inline int http_status(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return 200;
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::OUT_OF_RANGE:
    case grpc::StatusCode::FAILED_PRECONDITION: return 400;
    case grpc::StatusCode::UNAUTHENTICATED: return 401;
    case grpc::StatusCode::PERMISSION_DENIED: return 403;
    case grpc::StatusCode::NOT_FOUND: return 404;
    case grpc::StatusCode::ALREADY_EXISTS:
    case grpc::StatusCode::ABORTED: return 409;
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
    case grpc::StatusCode::UNAVAILABLE: return 503;
    case grpc::StatusCode::DEADLINE_EXCEEDED: return 504;
    case grpc::StatusCode::UNIMPLEMENTED: return 501;
    default: return 500;
  }
}

}  // namespace omniview
