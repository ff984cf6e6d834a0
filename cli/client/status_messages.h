// Turns a failed gRPC call into a message that tells a person what to do next.
#pragma once

#include <grpcpp/support/status.h>

#include <string>

namespace omniview::cli {

struct CallContext {
  std::string server;  // HOST:PORT, for "cannot reach ..."
  bool tls = false;
  bool has_token = false;
  std::string token_origin;  // where the token came from, if any
  double deadline_s = 0;     // 0: the call had none (a stream)
  bool client_certificate = false;  // --tls-cert given
  bool client_certificate_requested = false;  // the server asks for one (see tls_probe.h)
};

// `what` names what was asked for ("view 'front'", "GetStatus"); it may be empty.
std::string describe_status(const grpc::Status& status, const CallContext& call, const std::string& what);

}  // namespace omniview::cli
