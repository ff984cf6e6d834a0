// What every RPC of OmniviewService shares: errors turned into statuses a person can act
// on, the role check, the request-bounds check and the poll interval of waiting streams.
#pragma once

#include <chrono>
#include <string>

#include <grpcpp/support/status.h>

#include "server/api/request_bounds.h"
#include "server/auth/permissions.h"
#include "server/pipeline/api_error.h"

namespace omniview::service_support {

// Runs `body`, turning the pipeline's and core's exceptions into statuses.
// A status message travels in a header: however it was built, keep it far below gRPC's
// metadata limit (8 KiB), or the client sees RESOURCE_EXHAUSTED instead of the refusal.
inline grpc::Status bounded(grpc::StatusCode code, std::string message) {
  constexpr size_t kMaxStatusMessage = 2048;
  if (message.size() > kMaxStatusMessage) message = message.substr(0, kMaxStatusMessage) + "... (cut)";
  return grpc::Status(code, message);
}

template <typename F>
grpc::Status guarded(F&& body) {
  try {
    const grpc::Status s = body();
    return s.ok() ? s : bounded(s.error_code(), s.error_message());
  } catch (const ApiError& e) {
    return bounded(e.code, e.what());
  } catch (const std::invalid_argument& e) {
    return bounded(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  } catch (const std::exception& e) {
    return bounded(grpc::StatusCode::INTERNAL, std::string("internal error: ") + e.what());
  } catch (...) {
    return bounded(grpc::StatusCode::INTERNAL, "internal error");
  }
}

// The role the RPC needs comes from the one table (server/auth/permissions.h), by the
// handler's own name: a handler cannot say a role of its own.
#define OMNIVIEW_AUTHORIZE(ctx)                                                                    \
  do {                                                                                             \
    const grpc::Status auth_status = auth_.check(*(ctx), ::omniview::permissions::rpc_role(__func__)); \
    if (!auth_status.ok()) return auth_status;                                                     \
  } while (0)

// After authorization: every field of the request within its bounds (request_bounds.h).
#define OMNIVIEW_CHECK_BOUNDS(req)                                    \
  do {                                                                \
    const grpc::Status bounds_status = check_request_bounds(*(req));  \
    if (!bounds_status.ok()) return bounds_status;                    \
  } while (0)

inline constexpr auto kPoll = std::chrono::milliseconds(100);  // how often a waiting stream checks for cancellation

}  // namespace omniview::service_support
