#include "spot_adapter/mock/server/tls_credentials.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <grpcpp/security/server_credentials.h>

#include "spot_adapter/mock/auth/certificates.h"

namespace omniview::spot_mock {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

std::shared_ptr<grpc::ServerCredentials> mock_server_credentials(const std::string& certs_dir) {
  grpc::SslServerCredentialsOptions options;
  for (const auto& authority : mock_authorities()) {
    options.pem_key_cert_pairs.push_back({read_file(key_file(certs_dir, authority)),
                                          read_file(cert_file(certs_dir, authority))});
  }
  return grpc::SslServerCredentials(options);
}

}  // namespace omniview::spot_mock
