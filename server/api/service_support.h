// What every RPC of OmniviewService shares: errors turned into statuses a person can act
// on, the role check and the request-bounds check.
#pragma once


#include <grpcpp/support/status.h>

#include "server/api/request_bounds.h"
#include "server/auth/permissions.h"
#include "server/status/failure.h"

namespace omniview::service_support {

// Runs `body`, turning any exception into the status server/status/failure.h says for it.
template <typename F>
grpc::Status guarded(F&& body) {
  try {
    const grpc::Status s = body();
    return s.ok() ? s : grpc_status(s.error_code(), s.error_message());
  } catch (...) {
    return grpc_status(current_failure());
  }
}

// A stream's subscriber closed by the pipeline (view deleted, shutdown): the status it says.
template <typename S>
grpc::Status closed_status(const S& subscriber) {
  return grpc_status(grpc_code(subscriber.close_kind()), subscriber.close_reason());
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

}  // namespace omniview::service_support
