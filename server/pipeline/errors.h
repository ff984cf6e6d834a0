// What can go wrong in the engine, in its own words: the kind tells a program what
// happened, the message tells a person what to do about it. The engine knows no front end;
// server/status/failure.h says each kind as a gRPC status, an HTTP status and the name the
// WebSocket protocols send.
#pragma once

#include <stdexcept>
#include <string>

namespace omniview {

enum class ErrorKind {
  kCancelled,           // the client went away or stopped
  kInvalidArgument,     // the request is wrong, whatever the state
  kDeadlineExceeded,
  kNotFound,            // no such view, source, camera, session
  kAlreadyExists,
  kPermissionDenied,
  kResourceExhausted,   // a limit: too many views, streams, sessions
  kFailedPrecondition,  // right request, wrong state (no black box configured, ...)
  kAborted,
  kOutOfRange,
  kUnimplemented,
  kInternal,
  kUnavailable,         // the source or the daemon cannot serve it now
  kUnauthenticated,
};

struct PipelineError : std::runtime_error {
  PipelineError(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind(kind) {}
  ErrorKind kind;
};

}  // namespace omniview
