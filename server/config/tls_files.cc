#include "server/config/tls_files.h"

#include <memory>

#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

namespace omniview {
namespace {

using Bio = std::unique_ptr<BIO, decltype(&BIO_free)>;
using Cert = std::unique_ptr<X509, decltype(&X509_free)>;
using Key = std::unique_ptr<EVP_PKEY, decltype(&EVP_PKEY_free)>;

Bio open(const std::string& file) { return Bio(BIO_new_file(file.c_str(), "rb"), BIO_free); }

// A passphrase prompt would block the daemon's start; gRPC cannot use an encrypted key anyway.
int no_passphrase(char*, int, int, void*) { return 0; }

Cert read_certificate(const std::string& file) {
  const Bio bio = open(file);
  Cert cert(bio ? PEM_read_bio_X509(bio.get(), nullptr, no_passphrase, nullptr) : nullptr, X509_free);
  ERR_clear_error();  // OpenSSL's queue is per thread; leave nothing behind for gRPC to find
  return cert;
}

Key read_private_key(const std::string& file) {
  const Bio bio = open(file);
  Key key(bio ? PEM_read_bio_PrivateKey(bio.get(), nullptr, no_passphrase, nullptr) : nullptr, EVP_PKEY_free);
  ERR_clear_error();
  return key;
}

bool has_private_key(const std::string& file) { return read_private_key(file) != nullptr; }
bool has_certificate(const std::string& file) { return read_certificate(file) != nullptr; }

}  // namespace

std::string certificate_file_problem(const std::string& file, const std::string& key) {
  if (has_certificate(file)) return "";
  std::string why = "'" + file + "' holds no PEM certificate (-----BEGIN CERTIFICATE-----)";
  if (has_private_key(file)) {
    why += key == "tls.cert" ? "; it holds a private key: are tls.cert and tls.key swapped?"
                             : "; it holds a private key, which never belongs in " + key;
  }
  return why;
}

std::string private_key_file_problem(const std::string& file) {
  if (has_private_key(file)) return "";
  std::string why = "'" + file + "' holds no unencrypted PEM private key (-----BEGIN ... PRIVATE KEY-----)";
  if (has_certificate(file)) why += "; it holds a certificate: are tls.cert and tls.key swapped?";
  return why;
}

std::string key_pair_problem(const std::string& cert_file, const std::string& key_file) {
  const Cert cert = read_certificate(cert_file);
  const Key key = read_private_key(key_file);
  if (!cert || !key) return "cannot read the certificate or the key";
  const bool match = X509_check_private_key(cert.get(), key.get()) == 1;
  ERR_clear_error();
  if (match) return "";
  return "the private key in '" + key_file + "' does not belong to the certificate in '" + cert_file +
         "' (tls.cert): give the key the certificate was issued for";
}

}  // namespace omniview
