#include "cli/client/tls_probe.h"

#include <netdb.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <openssl/err.h>
#include <openssl/ssl.h>

#include <memory>

namespace omniview::cli {
namespace {

// Called by OpenSSL when the server sends a CertificateRequest; answers "no certificate".
int note_request(SSL* ssl, X509**, EVP_PKEY**) {
  *static_cast<bool*>(SSL_get_app_data(ssl)) = true;
  return 0;
}

int connect_to(const std::string& host, const std::string& port, int timeout_ms) {
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), port.c_str(), &hints, &found) != 0) return -1;
  int fd = -1;
  for (addrinfo* a = found; a && fd < 0; a = a->ai_next) {
    fd = socket(a->ai_family, a->ai_socktype, a->ai_protocol);
    if (fd < 0) continue;
    timeval tv{timeout_ms / 1000, (timeout_ms % 1000) * 1000};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    if (connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
      close(fd);
      fd = -1;
    }
  }
  freeaddrinfo(found);
  return fd;
}

}  // namespace

bool server_requests_client_certificate(const std::string& host_port, int timeout_ms) {
  const auto colon = host_port.rfind(':');
  if (colon == std::string::npos) return false;
  std::string host = host_port.substr(0, colon);
  if (host.size() > 1 && host.front() == '[') host = host.substr(1, host.size() - 2);  // [::1]:port
  const int fd = connect_to(host, host_port.substr(colon + 1), timeout_ms);
  if (fd < 0) return false;
  std::unique_ptr<SSL_CTX, decltype(&SSL_CTX_free)> ctx(SSL_CTX_new(TLS_client_method()), SSL_CTX_free);
  bool requested = false;
  if (ctx) {
    SSL_CTX_set_verify(ctx.get(), SSL_VERIFY_NONE, nullptr);
    SSL_CTX_set_client_cert_cb(ctx.get(), note_request);
    static const unsigned char kAlpn[] = {2, 'h', '2'};  // as gRPC offers it
    SSL_CTX_set_alpn_protos(ctx.get(), kAlpn, sizeof kAlpn);
    std::unique_ptr<SSL, decltype(&SSL_free)> ssl(SSL_new(ctx.get()), SSL_free);
    if (ssl) {
      SSL_set_app_data(ssl.get(), &requested);
      SSL_set_fd(ssl.get(), fd);
      SSL_set_tlsext_host_name(ssl.get(), host.c_str());
      SSL_connect(ssl.get());  // the request, if any, arrives during the handshake
      SSL_shutdown(ssl.get());
    }
  }
  ERR_clear_error();
  close(fd);
  return requested;
}

}  // namespace omniview::cli
