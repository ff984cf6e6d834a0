// The listening port's credentials from the config's `tls:` section.
#pragma once

#include <memory>
#include <optional>

#include <grpcpp/security/server_credentials.h>

#include "server/config/daemon_config.h"

namespace omniview {

// Insecure (plaintext) when `tls` is absent. With tls.client_ca_file, clients must present
// a certificate signed by that CA (requested, required and verified). Throws ConfigError
// naming the file when a PEM file cannot be read or holds no PEM block of the right kind.
std::shared_ptr<grpc::ServerCredentials> make_server_credentials(const std::optional<TlsConfig>& tls);

}  // namespace omniview
