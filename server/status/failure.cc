#include "server/status/failure.h"

#include <array>
#include <exception>
#include <utility>

namespace omniview {

namespace {

struct KindInfo {
  ErrorKind kind;
  grpc::StatusCode grpc;
  int http;  // as gRPC's own HTTP mapping (grpc/doc/http-grpc-status-mapping), read the other way
  std::string_view name;
};

constexpr std::array<KindInfo, 14> kKinds = {{
    {ErrorKind::kCancelled, grpc::StatusCode::CANCELLED, 500, "CANCELLED"},
    {ErrorKind::kInvalidArgument, grpc::StatusCode::INVALID_ARGUMENT, 400, "INVALID_ARGUMENT"},
    {ErrorKind::kDeadlineExceeded, grpc::StatusCode::DEADLINE_EXCEEDED, 504, "DEADLINE_EXCEEDED"},
    {ErrorKind::kNotFound, grpc::StatusCode::NOT_FOUND, 404, "NOT_FOUND"},
    {ErrorKind::kAlreadyExists, grpc::StatusCode::ALREADY_EXISTS, 409, "ALREADY_EXISTS"},
    {ErrorKind::kPermissionDenied, grpc::StatusCode::PERMISSION_DENIED, 403, "PERMISSION_DENIED"},
    {ErrorKind::kResourceExhausted, grpc::StatusCode::RESOURCE_EXHAUSTED, 503, "RESOURCE_EXHAUSTED"},
    {ErrorKind::kFailedPrecondition, grpc::StatusCode::FAILED_PRECONDITION, 400, "FAILED_PRECONDITION"},
    {ErrorKind::kAborted, grpc::StatusCode::ABORTED, 409, "ABORTED"},
    {ErrorKind::kOutOfRange, grpc::StatusCode::OUT_OF_RANGE, 400, "OUT_OF_RANGE"},
    {ErrorKind::kUnimplemented, grpc::StatusCode::UNIMPLEMENTED, 501, "UNIMPLEMENTED"},
    {ErrorKind::kInternal, grpc::StatusCode::INTERNAL, 500, "INTERNAL"},
    {ErrorKind::kUnavailable, grpc::StatusCode::UNAVAILABLE, 503, "UNAVAILABLE"},
    {ErrorKind::kUnauthenticated, grpc::StatusCode::UNAUTHENTICATED, 401, "UNAUTHENTICATED"},
}};

const KindInfo& info(ErrorKind kind) {
  for (const auto& k : kKinds) {
    if (k.kind == kind) return k;
  }
  return kKinds[11];  // kInternal
}

}  // namespace

Failure current_failure() {
  try {
    throw;
  } catch (const PipelineError& e) {
    return {e.kind, e.what()};
  } catch (const std::invalid_argument& e) {
    return {ErrorKind::kInvalidArgument, e.what()};
  } catch (const std::exception& e) {
    return {ErrorKind::kInternal, std::string("internal error: ") + e.what()};
  } catch (...) {
    return {ErrorKind::kInternal, "internal error"};
  }
}

grpc::StatusCode grpc_code(ErrorKind kind) { return info(kind).grpc; }

ErrorKind kind_of(grpc::StatusCode code) {
  for (const auto& k : kKinds) {
    if (k.grpc == code) return k.kind;
  }
  return ErrorKind::kInternal;  // UNKNOWN, DATA_LOSS: nothing here says those
}

int http_status(ErrorKind kind) { return info(kind).http; }

std::string_view status_name(ErrorKind kind) { return info(kind).name; }

grpc::Status grpc_status(grpc::StatusCode code, std::string message) {
  constexpr size_t kMaxStatusMessage = 2048;
  if (message.size() > kMaxStatusMessage) message = message.substr(0, kMaxStatusMessage) + "... (cut)";
  return grpc::Status(code, message);
}

}  // namespace omniview
