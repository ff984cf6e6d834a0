#include "cli/client/status_messages.h"

#include <sstream>

namespace omniview::cli {
namespace {

// "view 'front': " or "" when the caller named nothing.
std::string prefix(const std::string& what) { return what.empty() ? "" : what + ": "; }

std::string server_said(const grpc::Status& status) {
  return status.error_message().empty() ? "" : " (" + status.error_message() + ")";
}

std::string unreachable(const grpc::Status& status, const CallContext& call) {
  std::ostringstream m;
  m << "cannot reach omniviewd at " << call.server << " (is it running? is --server or OMNIVIEW_SERVER right?";
  if (call.tls) {
    m << " does the daemon use TLS, does --tls-ca hold the CA that signed its certificate, and does the"
         " certificate name the host (else --tls-server-name NAME)?";
  } else {
    m << " if the daemon uses TLS, pass --tls-ca FILE.";
  }
  m << ")";
  if (!status.error_message().empty()) m << "\n  gRPC said: " << status.error_message();
  return m.str();
}

}  // namespace

std::string describe_status(const grpc::Status& status, const CallContext& call, const std::string& what) {
  const std::string msg = status.error_message();
  switch (status.error_code()) {
    case grpc::StatusCode::OK:
      return "ok";
    case grpc::StatusCode::UNAVAILABLE:
      return unreachable(status, call);
    case grpc::StatusCode::DEADLINE_EXCEEDED: {
      std::ostringstream m;
      m << prefix(what) << "omniviewd at " << call.server << " did not answer";
      if (call.deadline_s > 0) m << " within " << call.deadline_s << " s (raise it with --timeout S)";
      return m.str();
    }
    case grpc::StatusCode::UNAUTHENTICATED:
      if (!call.has_token) {
        return "omniviewd at " + call.server + " requires a token" + server_said(status) +
               ": pass --token-file FILE or set OMNIVIEW_TOKEN";
      }
      return "omniviewd at " + call.server + " rejected the token from " + call.token_origin + server_said(status) +
             ": check the token, or pass another with --token-file FILE or OMNIVIEW_TOKEN";
    case grpc::StatusCode::PERMISSION_DENIED:
      return prefix(what) + "permission denied" + server_said(status) +
             ": this needs an operator token (pass one with --token-file FILE or OMNIVIEW_TOKEN)";
    case grpc::StatusCode::NOT_FOUND:
      return msg.empty() ? prefix(what) + "not found" : msg;
    case grpc::StatusCode::ALREADY_EXISTS:
      return (msg.empty() ? prefix(what) + "already exists" : msg) +
             " (change it with 'omniview views update', or delete it first)";
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::OUT_OF_RANGE:
      return prefix(what) + (msg.empty() ? "rejected by omniviewd" : msg);
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
      return prefix(what) + "omniviewd refused: " + (msg.empty() ? "a limit was reached" : msg) +
             " (the daemon's limits are set in its config)";
    case grpc::StatusCode::UNIMPLEMENTED:
      return prefix(what) + "omniviewd at " + call.server + " does not implement this call" + server_said(status) +
             "; is it an older version than this client?";
    case grpc::StatusCode::CANCELLED:
      return prefix(what) + "cancelled" + server_said(status);
    case grpc::StatusCode::ABORTED:
      return prefix(what) + "aborted by a concurrent change" + server_said(status) + "; try again";
    case grpc::StatusCode::INTERNAL:
    case grpc::StatusCode::UNKNOWN:
    case grpc::StatusCode::DATA_LOSS:
    default:
      return prefix(what) + "omniviewd failed" + server_said(status) + "; its log may say more";
  }
}

}  // namespace omniview::cli
