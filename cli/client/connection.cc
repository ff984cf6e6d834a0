#include "cli/client/connection.h"

#include <grpc/support/log.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "cli/client/status_messages.h"
#include "cli/client/tls_probe.h"

namespace omniview::cli {
namespace {

// Frames of big views (RAW 4K RGB is 25 MB) must fit; the daemon caps what it sends.
constexpr int kMaxReceiveBytes = 256 << 20;

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

std::string read_file(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UsageError("cannot read " + what + " '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

const std::vector<std::string>& connection_flags() {
  static const std::vector<std::string> flags{"server",          "tls-ca",     "tls-cert", "tls-key",
                                              "tls-server-name", "token-file", "timeout"};
  return flags;
}

const char* connection_help() {
  return R"(connection:
  --server HOST:PORT     omniviewd's address (default $OMNIVIEW_SERVER, else 127.0.0.1:50051)
  --tls-ca FILE          connect with TLS, trusting the CA certificate(s) in FILE (PEM)
  --tls-cert FILE        with --tls-key: this client's certificate (PEM), for a daemon
                         that requires client certificates (its config has tls.client_ca)
  --tls-key FILE         the private key (PEM) of --tls-cert
  --tls-server-name NAME the name the server certificate must carry (default: HOST)
  --token-file FILE      file holding the access token (default $OMNIVIEW_TOKEN, the token
                         itself, or $OMNIVIEW_TOKEN_FILE)
  --timeout S            deadline of each request, seconds (default 10; streams have none)
)";
}

std::string read_token_file(const std::string& path) {
  std::istringstream lines(read_file(path, "token file"));
  std::string first;
  std::getline(lines, first);
  const std::string token = trim(first);
  if (token.empty()) throw UsageError("token file '" + path + "' is empty");
  return token;
}

ConnectionOptions connection_options(const Args& args) {
  ConnectionOptions o;
  o.server = args.get("server", env("OMNIVIEW_SERVER"));
  if (o.server.empty()) o.server = kDefaultServer;
  if (o.server.find(':') == std::string::npos) throw UsageError("--server '" + o.server + "': expected HOST:PORT");

  o.tls_ca_file = args.get("tls-ca");
  o.tls_server_name = args.get("tls-server-name");
  if (!o.tls_server_name.empty() && o.tls_ca_file.empty()) throw UsageError("--tls-server-name needs --tls-ca");
  o.tls_cert_file = args.get("tls-cert");
  o.tls_key_file = args.get("tls-key");
  if (o.tls_cert_file.empty() != o.tls_key_file.empty()) {
    throw UsageError("--tls-cert and --tls-key go together: give the client certificate and its key");
  }
  if (!o.tls_cert_file.empty() && o.tls_ca_file.empty()) {
    throw UsageError("--tls-cert needs --tls-ca (the CA that signed the daemon's certificate)");
  }

  if (args.has("token-file")) {
    o.token = read_token_file(args.get("token-file"));
    o.token_origin = "--token-file " + args.get("token-file");
  } else if (!trim(env("OMNIVIEW_TOKEN")).empty()) {
    o.token = trim(env("OMNIVIEW_TOKEN"));
    o.token_origin = "OMNIVIEW_TOKEN";
  } else if (!env("OMNIVIEW_TOKEN_FILE").empty()) {
    o.token = read_token_file(env("OMNIVIEW_TOKEN_FILE"));
    o.token_origin = "OMNIVIEW_TOKEN_FILE " + env("OMNIVIEW_TOKEN_FILE");
  }

  if (args.has("timeout")) {
    double s = 0;
    try {
      size_t used = 0;
      s = std::stod(args.get("timeout"), &used);
      if (used != args.get("timeout").size()) s = -1;
    } catch (const std::exception&) {
      s = -1;
    }
    if (!(s > 0) || !std::isfinite(s)) throw UsageError("--timeout: expected seconds > 0");
    o.deadline = std::chrono::milliseconds(static_cast<int64_t>(s * 1000));
  }
  return o;
}

namespace {
// gRPC logs connection trouble to stderr on its own; our messages say it in words a user
// can act on, so its lines stay hidden unless GRPC_VERBOSITY asks for them.
void quiet_grpc_log(gpr_log_func_args*) {}
}  // namespace

Connection::Connection(ConnectionOptions options) : options_(std::move(options)) {
  if (std::getenv("GRPC_VERBOSITY") == nullptr) gpr_set_log_function(quiet_grpc_log);
  grpc::ChannelArguments channel_args;
  channel_args.SetMaxReceiveMessageSize(kMaxReceiveBytes);
  std::shared_ptr<grpc::ChannelCredentials> credentials;
  if (options_.tls_ca_file.empty()) {
    credentials = grpc::InsecureChannelCredentials();
  } else {
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = read_file(options_.tls_ca_file, "--tls-ca file");
    // gRPC only logs an unusable CA file and then fails every call as "unavailable".
    if (ssl.pem_root_certs.find("-----BEGIN CERTIFICATE-----") == std::string::npos) {
      throw UsageError("--tls-ca '" + options_.tls_ca_file + "' holds no PEM certificate");
    }
    if (!options_.tls_cert_file.empty()) {
      ssl.pem_cert_chain = read_file(options_.tls_cert_file, "--tls-cert file");
      ssl.pem_private_key = read_file(options_.tls_key_file, "--tls-key file");
      if (ssl.pem_cert_chain.find("-----BEGIN CERTIFICATE-----") == std::string::npos) {
        throw UsageError("--tls-cert '" + options_.tls_cert_file + "' holds no PEM certificate");
      }
      if (ssl.pem_private_key.find("PRIVATE KEY-----") == std::string::npos) {
        throw UsageError("--tls-key '" + options_.tls_key_file + "' holds no PEM private key");
      }
    }
    credentials = grpc::SslCredentials(ssl);
    if (!options_.tls_server_name.empty()) channel_args.SetSslTargetNameOverride(options_.tls_server_name);
  }
  channel_ = grpc::CreateCustomChannel(options_.server, credentials, channel_args);
  stub_ = v1::Omniview::NewStub(channel_);
}

void Connection::prepare(grpc::ClientContext& context, bool unary) const {
  // Plain metadata rather than call credentials: gRPC refuses call credentials on a
  // plaintext channel, and a loopback daemon without TLS may still want a token.
  if (!options_.token.empty()) context.AddMetadata("authorization", "Bearer " + options_.token);
  if (unary) context.set_deadline(std::chrono::system_clock::now() + options_.deadline);
}

void Connection::check(const grpc::Status& status, const std::string& what) const {
  if (status.ok()) return;
  CallContext call{options_.server, !options_.tls_ca_file.empty(), !options_.token.empty(), options_.token_origin,
                   options_.deadline.count() / 1000.0};
  call.client_certificate = !options_.tls_cert_file.empty();
  // gRPC reports a refused missing client certificate as "Socket closed": ask the server.
  call.client_certificate_requested = status.error_code() == grpc::StatusCode::UNAVAILABLE && call.tls &&
                                      !call.client_certificate && server_requests_client_certificate(options_.server);
  throw RpcError(status.error_code(), describe_status(status, call, what));
}

}  // namespace omniview::cli
