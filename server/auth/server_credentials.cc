#include "server/auth/server_credentials.h"

#include <fstream>
#include <iterator>
#include <string>

#include "core/io/yaml_reader.h"  // ConfigError

namespace omniview {
namespace {

// The file's text; `what` names its role in the message ("tls.cert"). Checked for a PEM
// marker here because gRPC would only say "failed to build the server" much later.
std::string read_pem(const std::string& file, const char* what, const char* marker) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(file + ": cannot read " + what + " (PEM file)");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.find(marker) == std::string::npos) {
    throw ConfigError(file + ": " + what + " is not a PEM file (no '" + marker + "' block)");
  }
  return text;
}

}  // namespace

std::shared_ptr<grpc::ServerCredentials> make_server_credentials(const std::optional<TlsConfig>& tls) {
  if (!tls) return grpc::InsecureServerCredentials();
  grpc::SslServerCredentialsOptions options;
  options.pem_key_cert_pairs.push_back({read_pem(tls->key_file, "tls.key", "PRIVATE KEY-----"),
                                        read_pem(tls->cert_file, "tls.cert", "-----BEGIN CERTIFICATE-----")});
  if (!tls->client_ca_file.empty()) {
    options.pem_root_certs = read_pem(tls->client_ca_file, "tls.client_ca", "-----BEGIN CERTIFICATE-----");
    options.client_certificate_request = GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY;
  } else {
    options.client_certificate_request = GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE;
  }
  return grpc::SslServerCredentials(options);
}

}  // namespace omniview
