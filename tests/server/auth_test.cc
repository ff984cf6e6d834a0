// Tokens and roles through the real daemon, in plaintext and over TLS with a test CA.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "daemon_process.h"

namespace omniview::testing {
namespace {

const char* kTokens = R"(tokens:
  - {role: viewer, token: viewer-secret-123}
  - {role: operator, token: operator-secret-456}
views:
  - {name: front, type: perspective, width: 128, height: 64}
)";

v1::CreateViewRequest a_view() {
  v1::CreateViewRequest req;
  req.mutable_spec()->set_name("other");
  req.mutable_spec()->set_type(v1::PERSPECTIVE);
  return req;
}

TEST(Auth, RolesDecideWhatACallerMayDo) {
  TempDir dir;
  DaemonProcess daemon(dir, example_config(10, kTokens));
  auto stub = make_stub(daemon.address());
  v1::ListViewsResponse list;
  v1::View view;

  auto s = stub->ListViews(make_context().get(), {}, &list);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_NE(s.error_message().find("Bearer"), std::string::npos) << s.error_message();
  s = stub->ListViews(make_context("wrong-token").get(), {}, &list);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(s.error_message().find("wrong-token"), std::string::npos);  // secrets are never echoed

  EXPECT_TRUE(stub->ListViews(make_context("viewer-secret-123").get(), {}, &list).ok());
  s = stub->CreateView(make_context("viewer-secret-123").get(), a_view(), &view);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_NE(s.error_message().find("operator"), std::string::npos);
  v1::UpdateViewRequest update;
  update.set_name("front");
  update.mutable_delta()->set_yaw_deg(5);
  EXPECT_EQ(stub->UpdateView(make_context("viewer-secret-123").get(), update, &view).error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
  v1::DeleteViewRequest del;
  del.set_name("front");
  v1::DeleteViewResponse deleted;
  EXPECT_EQ(stub->DeleteView(make_context("viewer-secret-123").get(), del, &deleted).error_code(),
            grpc::StatusCode::PERMISSION_DENIED);

  // A viewer may watch.
  v1::StreamFramesRequest req;
  req.set_view("front");
  auto ctx = make_context("viewer-secret-123");
  auto reader = stub->StreamFrames(ctx.get(), req);
  v1::Frame f;
  EXPECT_TRUE(reader->Read(&f));
  ctx->TryCancel();
  reader->Finish();
  // An unauthenticated stream ends at once.
  auto ctx2 = make_context();
  auto reader2 = stub->StreamFrames(ctx2.get(), req);
  EXPECT_FALSE(reader2->Read(&f));
  EXPECT_EQ(reader2->Finish().error_code(), grpc::StatusCode::UNAUTHENTICATED);

  EXPECT_TRUE(stub->CreateView(make_context("operator-secret-456").get(), a_view(), &view).ok());
  EXPECT_TRUE(stub->UpdateView(make_context("operator-secret-456").get(), update, &view).ok());
  EXPECT_TRUE(stub->DeleteView(make_context("operator-secret-456").get(), del, &deleted).ok());

  const std::string log = daemon.log();
  EXPECT_EQ(log.find("secret"), std::string::npos) << log;
  // Who was let in and who was refused, by the tokens' labels.
  EXPECT_NE(log.find("authenticated with tokens[1] (inline) (operator)"), std::string::npos) << log;
  EXPECT_NE(log.find("with tokens[0] (inline): this call needs the operator role"), std::string::npos) << log;
  EXPECT_NE(log.find(": unknown token"), std::string::npos) << log;
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Auth, TlsWithATestCaAndClientCertificates) {
  TempDir dir;
  const auto certs = dir.path() / "certs";
  ASSERT_EQ(std::system(("bash " + std::string(OMNIVIEW_SOURCE_DIR) + "/scripts/make-test-certs.sh " +
                         certs.string()).c_str()),
            0);
  std::string tls = "tls: {cert: " + (certs / "server.crt").string() + ", key: " + (certs / "server.key").string() +
                    ", client_ca: " + (certs / "ca.crt").string() + "}\n";
  DaemonProcess daemon(dir, example_config(10, tls + kTokens));
  const std::string port = daemon.address().substr(daemon.address().rfind(':') + 1);
  const std::string host = "localhost:" + port;  // the name in the server certificate

  grpc::SslCredentialsOptions with_cert;
  with_cert.pem_root_certs = read_file(certs / "ca.crt");
  with_cert.pem_cert_chain = read_file(certs / "client.crt");
  with_cert.pem_private_key = read_file(certs / "client.key");
  auto stub = make_stub(host, grpc::SslCredentials(with_cert));
  v1::ListViewsResponse list;
  const auto ok = stub->ListViews(make_context("viewer-secret-123").get(), {}, &list);
  EXPECT_TRUE(ok.ok()) << ok.error_message();
  EXPECT_EQ(list.views_size(), 1);

  grpc::SslCredentialsOptions no_cert;
  no_cert.pem_root_certs = with_cert.pem_root_certs;
  auto anonymous = make_stub(host, grpc::SslCredentials(no_cert));
  EXPECT_FALSE(anonymous->ListViews(make_context("viewer-secret-123", std::chrono::seconds(3)).get(), {}, &list).ok());

  auto plaintext = make_stub(host);
  EXPECT_FALSE(plaintext->ListViews(make_context("viewer-secret-123", std::chrono::seconds(3)).get(), {}, &list).ok());

  // The CLI: without a client certificate it says that one is needed; with one it works.
  const std::string token = dir.write("viewer.token", "viewer-secret-123\n");
  const std::string cli = std::string(OMNIVIEW_CLI) + " views list --server " + host + " --tls-ca " +
                          (certs / "ca.crt").string() + " --token-file " + token + " --timeout 5";
  const auto refused = run_process(cli);
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_NE(refused.output.find("requires a client certificate and none was given"), std::string::npos)
      << refused.output;
  EXPECT_NE(refused.output.find("--tls-cert FILE --tls-key FILE"), std::string::npos) << refused.output;
  const auto with_certificate = run_process(cli + " --tls-cert " + (certs / "client.crt").string() + " --tls-key " +
                                            (certs / "client.key").string());
  EXPECT_EQ(with_certificate.exit_code, 0) << with_certificate.output;
  EXPECT_NE(with_certificate.output.find("front"), std::string::npos) << with_certificate.output;

  // The Python example likewise, its token from OMNIVIEW_TOKEN_FILE.
  const std::string python = "env -u OMNIVIEW_TOKEN OMNIVIEW_TOKEN_FILE=" + token +
                             " XDG_CACHE_HOME=" + (dir.path() / "cache").string() + " " + OMNIVIEW_DEBIAN_PYTHON +
                             " " + OMNIVIEW_SOURCE_DIR + "/examples/python/save_frames.py front --frames 1 -o " +
                             (dir.path() / "py").string() + " --server " + host + " --tls-ca " +
                             (certs / "ca.crt").string();
  const auto py_refused = run_process(python);
  EXPECT_NE(py_refused.exit_code, 0) << py_refused.output;
  EXPECT_NE(py_refused.output.find("requires a client certificate"), std::string::npos) << py_refused.output;
  const auto py = run_process(python + " --tls-cert " + (certs / "client.crt").string() + " --tls-key " +
                              (certs / "client.key").string());
  EXPECT_EQ(py.exit_code, 0) << py.output;
  EXPECT_NE(py.output.find("saved 1 frames"), std::string::npos) << py.output;
}

// A loop of bad tokens once wrote 500 log lines in 0.6 s: refusals are logged a few at a
// time per peer host, the rest counted.
TEST(Auth, RefusalsAreLoggedAtABoundedRate) {
  TempDir dir;
  DaemonProcess daemon(dir, example_config(10, kTokens));
  v1::ListViewsResponse list;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 300; ++i) {
    auto stub = make_stub(daemon.address());  // a new connection each time: still one host
    ASSERT_EQ(stub->ListViews(make_context("bad-token-" + std::to_string(i)).get(), {}, &list).error_code(),
              grpc::StatusCode::UNAUTHENTICATED);
  }
  // The honest client is still served.
  EXPECT_TRUE(make_stub(daemon.address())->ListViews(make_context("viewer-secret-123").get(), {}, &list).ok());
  const std::string log = daemon.log();
  size_t lines = 0;
  for (size_t at = log.find("refused a call"); at != std::string::npos; at = log.find("refused a call", at + 1)) ++lines;
  EXPECT_GE(lines, 1u) << log;
  // Five a 10 s window (a slow sanitizer run may span several windows).
  const auto windows = 2 + std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now() - t0).count() / 10;
  EXPECT_LE(lines, static_cast<size_t>(5 * windows)) << "refusals flood the log:\n" << log.substr(0, 4000);
  EXPECT_EQ(log.find("bad-token"), std::string::npos) << "a token was logged";
}

// gRPC itself logs a failed TLS handshake per connection: a plaintext client in a loop
// must not flood the daemon's log through it either.
TEST(Auth, GrpcsOwnLogLinesAreRateLimited) {
  TempDir dir;
  const auto certs = dir.path() / "certs";
  ASSERT_EQ(std::system(("bash " + std::string(OMNIVIEW_SOURCE_DIR) + "/scripts/make-test-certs.sh " +
                         certs.string() + " > /dev/null").c_str()),
            0);
  const std::string tls =
      "tls: {cert: " + (certs / "server.crt").string() + ", key: " + (certs / "server.key").string() + "}\n";
  DaemonProcess daemon(dir, example_config(10, tls + kTokens));
  v1::ListViewsResponse list;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 40; ++i) {
    auto plaintext = make_stub(daemon.address());  // a new connection each time
    EXPECT_FALSE(plaintext->ListViews(make_context("viewer-secret-123", std::chrono::seconds(2)).get(), {}, &list).ok());
  }
  const std::string log = daemon.log();
  size_t lines = 0;
  for (size_t at = log.find("Handshake failed"); at != std::string::npos; at = log.find("Handshake failed", at + 1)) {
    ++lines;
  }
  const auto windows = 2 + std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now() - t0).count() / 10;
  EXPECT_GE(lines, 1u) << "gRPC no longer logs failed handshakes; this test needs another probe:\n" << log;
  EXPECT_LE(lines, static_cast<size_t>(5 * windows)) << "gRPC's handshake failures flood the log:\n" << log.substr(0, 4000);
}

}  // namespace
}  // namespace omniview::testing
