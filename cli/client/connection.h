// How client commands reach omniviewd: address, TLS, token and deadlines, taken from the
// flags every client command shares (and the OMNIVIEW_* environment variables).
#pragma once

#include <grpcpp/grpcpp.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "cli/args.h"
#include "omniview/v1/omniview.grpc.pb.h"

namespace omniview::cli {

constexpr const char* kDefaultServer = "127.0.0.1:50051";

struct ConnectionOptions {
  std::string server = kDefaultServer;        // HOST:PORT
  std::string tls_ca_file;                    // empty: plaintext
  std::string tls_server_name;                // overrides the name checked in the server certificate
  std::string tls_cert_file, tls_key_file;    // client certificate and key (mutual TLS); both or neither
  std::string token;                          // empty: send none
  std::string token_origin;                   // "--token-file F" or "OMNIVIEW_TOKEN", for messages
  std::chrono::milliseconds deadline{10000};  // unary calls only; streams run until done
};

// The flag names connection_options() reads; commands add them to Args::allow_only().
const std::vector<std::string>& connection_flags();
// The help text block describing them.
const char* connection_help();

// Flags first, then OMNIVIEW_SERVER, OMNIVIEW_TOKEN (the token itself) and
// OMNIVIEW_TOKEN_FILE. Throws UsageError for a bad value or an unreadable token file.
ConnectionOptions connection_options(const Args& args);

// A token file holds the token on its first line; surrounding whitespace is ignored.
std::string read_token_file(const std::string& path);

// A failed call, with a message a person can act on (see status_messages.h).
struct RpcError : std::runtime_error {
  RpcError(grpc::StatusCode code, const std::string& message) : std::runtime_error(message), code(code) {}
  grpc::StatusCode code;
};

class Connection {
 public:
  explicit Connection(ConnectionOptions options);

  v1::Omniview::Stub& stub() { return *stub_; }
  const ConnectionOptions& options() const { return options_; }

  // Adds the token and, for unary calls, the deadline to a fresh context.
  void prepare(grpc::ClientContext& context, bool unary) const;
  // Throws RpcError describing `status` unless it is OK; `what` names the call for the
  // message ("view 'front'").
  void check(const grpc::Status& status, const std::string& what) const;

 private:
  ConnectionOptions options_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::Omniview::Stub> stub_;
};

}  // namespace omniview::cli
