// Why a TLS connection failed, where gRPC only says "Socket closed": with TLS 1.3 a server
// that requires a client certificate refuses one that sent none only after the handshake,
// and gRPC does not pass that alert on.
#pragma once

#include <string>

namespace omniview::cli {

// Opens a TLS connection to HOST:PORT (without checking the server's certificate: only
// the server's request matters here) and returns whether the server asked for a client
// certificate. False on any connection error, or after `timeout_ms`.
bool server_requests_client_certificate(const std::string& host_port, int timeout_ms = 3000);

}  // namespace omniview::cli
