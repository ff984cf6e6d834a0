// The one seam between the engine's errors and what each front end says (gRPC, the
// console's and Foxglove's WebSockets, WHEP's HTTP, RTSP): an exception becomes a Failure
// here and nowhere else, and a Failure's kind has one gRPC status, one HTTP status and one
// name (gRPC's, which the WebSocket protocols send as their error code).
#pragma once

#include <string>
#include <string_view>

#include <grpcpp/support/status.h>

#include "server/pipeline/errors.h"

namespace omniview {

struct Failure {
  ErrorKind kind = ErrorKind::kInternal;
  std::string message;
};

// Call inside a catch block: the exception being handled as a Failure. PipelineError keeps
// its kind; std::invalid_argument (a parser's or a core check's "this input is wrong") is
// kInvalidArgument; anything else is kInternal, its text kept after "internal error: ".
Failure current_failure();

grpc::StatusCode grpc_code(ErrorKind kind);
ErrorKind kind_of(grpc::StatusCode code);  // a status a gRPC handler returned (not OK)
int http_status(ErrorKind kind);
std::string_view status_name(ErrorKind kind);  // "NOT_FOUND"

// A gRPC status whose message is kept far below gRPC's metadata limit (8 KiB; the message
// travels in a header): past it the client would read RESOURCE_EXHAUSTED instead.
grpc::Status grpc_status(grpc::StatusCode code, std::string message);
inline grpc::Status grpc_status(const Failure& f) { return grpc_status(grpc_code(f.kind), f.message); }

}  // namespace omniview
