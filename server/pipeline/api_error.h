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

}  // namespace omniview
