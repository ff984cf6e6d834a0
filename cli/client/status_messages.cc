#include "cli/client/status_messages.h"

#include <cctype>
#include <sstream>

namespace omniview::cli {
namespace {

// "view 'front': " or "" when the caller named nothing.
std::string prefix(const std::string& what) { return what.empty() ? "" : what + ": "; }

// The server's message, prefixed with what was asked for unless it names that already
// (no "view 'left': view 'left': ...").
std::string with_what(const std::string& what, const std::string& message) {
  if (what.empty() || message.find(what) != std::string::npos) return message;
  return what + ": " + message;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// TLS 1.3 servers refuse a missing client certificate with this alert after the handshake.
bool refused_for_missing_client_certificate(const grpc::Status& status) {
  std::string m = status.error_message();
  for (auto& c : m) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return contains(m, "certificate required") || contains(m, "certificate_required") ||
         contains(m, "peer did not return a certificate");
}

std::string server_said(const grpc::Status& status) {
  return status.error_message().empty() ? "" : " (" + status.error_message() + ")";
}

std::string unreachable(const grpc::Status& status, const CallContext& call) {
  std::ostringstream m;
  m << "cannot reach omniviewd at " << call.server << " (is it running? is --server or OMNIVIEW_SERVER right?";
  if (call.tls) {
    m << " does the daemon use TLS, does --tls-ca hold the CA that signed its certificate, and does the"
         " certificate name the host (else --tls-server-name NAME)?";
    if (!call.client_certificate) {
      m << " if the daemon requires client certificates (tls.client_ca), pass --tls-cert FILE --tls-key FILE.";
    }
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
      // The daemon's own UNAVAILABLE statuses say why; only the transport's mean "unreachable".
      if (contains(msg, "shutting down")) {
        // The daemon's message is just that; say it once.
        const bool only_that = msg == "omniviewd is shutting down";
        return prefix(what) + "omniviewd at " + call.server + " is shutting down" + (only_that ? "" : server_said(status)) +
               "; start it again, or wait for whatever restarts it";
      }
      if (contains(msg, "not delivering")) return with_what(what, msg);
      if (call.tls && !call.client_certificate &&
          (call.client_certificate_requested || refused_for_missing_client_certificate(status))) {
        return "omniviewd at " + call.server +
               " requires a client certificate and none was given: pass --tls-cert FILE --tls-key FILE "
               "(a certificate signed by the CA in the daemon's tls.client_ca)\n  gRPC said: " +
               msg;
      }
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
      // The daemon says which role the call needs; only where to get another token is added.
      return prefix(what) + "permission denied" + server_said(status) +
             ": pass an operator token with --token-file FILE or OMNIVIEW_TOKEN";
    case grpc::StatusCode::NOT_FOUND:
      return msg.empty() ? prefix(what) + "not found" : msg;
    case grpc::StatusCode::ALREADY_EXISTS:
      // The daemon's message already says what to do about it.
      return msg.empty() ? prefix(what) + "already exists (change it with 'omniview views update', or delete it first)"
                         : msg;
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::OUT_OF_RANGE:
      return msg.empty() ? prefix(what) + "rejected by omniviewd" : with_what(what, msg);
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
