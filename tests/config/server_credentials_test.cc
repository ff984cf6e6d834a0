// TLS credentials from real certificates (scripts/make-test-certs.sh): a server starts with
// them, a client that trusts the test CA completes the handshake, and with client_ca only
// a client holding a certificate from that CA does.
#include "server/auth/server_credentials.h"

#include <gtest/gtest.h>
#include <grpcpp/create_channel.h>
#include <grpcpp/generic/async_generic_service.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/server.h>
#include <grpcpp/server_builder.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include "test_support.h"

namespace omniview {
namespace {

using testing::expect_throw_containing;

std::string read(const std::string& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class ServerCredentials : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string command = "bash " OMNIVIEW_SOURCE_DIR "/scripts/make-test-certs.sh '" + dir_.path().string() + "'";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }

  TlsConfig tls(bool client_ca) const {
    return {dir_ / "server.crt", dir_ / "server.key", client_ca ? dir_ / "ca.crt" : ""};
  }

  // Starts a server and returns its port. gRPC refuses to start one without any service;
  // a generic one (answering UNIMPLEMENTED) is enough for a handshake.
  int start(const std::optional<TlsConfig>& config) {
    grpc::ServerBuilder builder;
    builder.RegisterCallbackGenericService(&generic_);
    int port = 0;
    builder.AddListeningPort("127.0.0.1:0", make_server_credentials(config), &port);
    server_ = builder.BuildAndStart();
    EXPECT_TRUE(server_) << "the server did not start";
    return port;
  }

  // Whether a client using `creds` reaches READY (a completed TLS handshake).
  static bool connects(int port, const std::shared_ptr<grpc::ChannelCredentials>& creds, int seconds) {
    const auto channel = grpc::CreateChannel("localhost:" + std::to_string(port), creds);
    return channel->WaitForConnected(std::chrono::system_clock::now() + std::chrono::seconds(seconds));
  }

  grpc::SslCredentialsOptions client_options(bool with_certificate) const {
    grpc::SslCredentialsOptions options;
    options.pem_root_certs = read(dir_ / "ca.crt");
    if (with_certificate) {
      options.pem_private_key = read(dir_ / "client.key");
      options.pem_cert_chain = read(dir_ / "client.crt");
    }
    return options;
  }

  void TearDown() override {
    if (server_) server_->Shutdown(std::chrono::system_clock::now());
  }

  testing::TempDir dir_;
  grpc::CallbackGenericService generic_;
  std::unique_ptr<grpc::Server> server_;
};

TEST_F(ServerCredentials, InsecureWithoutTls) {
  const int port = start(std::nullopt);
  ASSERT_GT(port, 0);
  EXPECT_TRUE(connects(port, grpc::InsecureChannelCredentials(), 10));
}

TEST_F(ServerCredentials, ServerCertificateForLocalhost) {
  const int port = start(tls(false));
  ASSERT_GT(port, 0);
  EXPECT_TRUE(connects(port, grpc::SslCredentials(client_options(false)), 10));
  // A plaintext client cannot talk to a TLS port.
  EXPECT_FALSE(connects(port, grpc::InsecureChannelCredentials(), 1));
}

TEST_F(ServerCredentials, ClientCaRequiresAClientCertificate) {
  const int port = start(tls(true));
  ASSERT_GT(port, 0);
  EXPECT_TRUE(connects(port, grpc::SslCredentials(client_options(true)), 10));
  EXPECT_FALSE(connects(port, grpc::SslCredentials(client_options(false)), 2));
}

TEST_F(ServerCredentials, ClientCertificateFromAnotherCaIsRefused) {
  testing::TempDir other;
  const std::string command = "bash " OMNIVIEW_SOURCE_DIR "/scripts/make-test-certs.sh '" + other.path().string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const int port = start(tls(true));
  ASSERT_GT(port, 0);
  auto options = client_options(false);
  options.pem_private_key = read(other / "client.key");
  options.pem_cert_chain = read(other / "client.crt");
  EXPECT_FALSE(connects(port, grpc::SslCredentials(options), 2));
}

TEST_F(ServerCredentials, UnreadableOrWrongFilesNameTheFile) {
  auto config = tls(true);
  config.cert_file = dir_ / "missing.crt";
  expect_throw_containing<ConfigError>([&] { make_server_credentials(config); },
                                       {dir_ / "missing.crt", "cannot read tls.cert"});
  config = tls(true);
  config.client_ca_file = dir_ / "server.key";  // a key where a certificate belongs
  expect_throw_containing<ConfigError>([&] { make_server_credentials(config); },
                                       {dir_ / "server.key", "tls.client_ca is not a PEM file"});
  config = tls(false);
  config.key_file = dir_ / "server.crt";
  expect_throw_containing<ConfigError>([&] { make_server_credentials(config); },
                                       {dir_ / "server.crt", "tls.key is not a PEM file"});
}

}  // namespace
}  // namespace omniview
