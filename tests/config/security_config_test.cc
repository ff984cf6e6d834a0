// Tokens, roles and TLS files in the daemon config, and the rule that a remote listen
// address needs TLS and tokens (or allow_insecure_remote).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>

#include "server/config/daemon_config.h"
#include "test_support.h"

namespace omniview {
namespace {

using testing::expect_throw_containing;

constexpr char kSources[] = "sources:\n  - {name: cam, type: images}\n";  // lines 1-2

class SecurityConfig : public ::testing::Test {
 protected:
  DaemonConfig parse(const std::string& text) {
    return parse_daemon_config(YamlReader::from_string(text, "d.yaml"), dir_.path().string());
  }
  void expect_error(const std::string& text, std::initializer_list<std::string> needles) {
    expect_throw_containing<ConfigError>([&] { parse(text); }, needles, text);
  }
  // A config whose tokens list starts on line 4.
  void expect_token_error(const std::string& entries, std::initializer_list<std::string> needles) {
    expect_error(std::string(kSources) + "tokens:\n" + entries, needles);
  }
  // Real test certificates (scripts/make-test-certs.sh) as s.crt, s.key and ca.crt in the
  // folder, and a second set under other/: the TLS files are read when the config loads.
  void write_certificates() {
    for (const std::string sub : {"", "other"}) {
      const std::string command =
          "bash " OMNIVIEW_SOURCE_DIR "/scripts/make-test-certs.sh '" + (dir_ / sub) + "' > /dev/null";
      ASSERT_EQ(std::system(command.c_str()), 0) << command;
    }
    std::filesystem::copy_file(dir_ / "server.crt", dir_ / "s.crt");
    std::filesystem::copy_file(dir_ / "server.key", dir_ / "s.key");
  }
  testing::TempDir dir_;
};

TEST_F(SecurityConfig, TokensFromEveryPlace) {
  dir_.write("viewer.token", "  viewer-secret-1 \n\n");
  ::setenv("OMNIVIEW_TEST_OPERATOR_TOKEN", "operator-secret-2\n", 1);
  const auto config = parse(std::string(kSources) +
                            "tokens:\n"
                            "  - {role: viewer, token_file: viewer.token}\n"
                            "  - {role: operator, name: station, token_env: OMNIVIEW_TEST_OPERATOR_TOKEN}\n"
                            "  - {role: viewer, token: inline-secret-3}\n");
  ::unsetenv("OMNIVIEW_TEST_OPERATOR_TOKEN");
  ASSERT_EQ(config.tokens.size(), 3u);
  EXPECT_EQ(config.tokens[0].token, "viewer-secret-1");
  EXPECT_EQ(config.tokens[0].role, Role::kViewer);
  EXPECT_EQ(config.tokens[0].label, "tokens[0] (" + (dir_ / "viewer.token") + ")");
  EXPECT_EQ(config.tokens[1].token, "operator-secret-2");
  EXPECT_EQ(config.tokens[1].role, Role::kOperator);
  EXPECT_EQ(config.tokens[1].label, "tokens[1] (station)");
  EXPECT_EQ(config.tokens[2].token, "inline-secret-3");
  EXPECT_EQ(config.tokens[2].label, "tokens[2] (inline)");
  for (const auto& t : config.tokens) EXPECT_EQ(t.label.find(t.token), std::string::npos);
}

TEST_F(SecurityConfig, TokenErrorsNameLineAndKey) {
  expect_token_error("  - {role: viewer}\n",
                     {"d.yaml:4: tokens[0]: no token given: set exactly one of token, token_file or token_env"});
  expect_token_error("  - {role: viewer, token: a, token_env: B}\n",
                     {"d.yaml:4: tokens[0]: more than one token given"});
  expect_token_error("  - {role: viewer, token: ''}\n", {"d.yaml:4: tokens[0].token: is empty"});
  expect_token_error("  - {role: viewer, token: '  '}\n", {"d.yaml:4: tokens[0].token: is empty"});
  expect_token_error("  - {role: viewer, token: 'two words'}\n",
                     {"d.yaml:4: tokens[0]: the token contains spaces", "authorization"});
  expect_token_error("  - {role: viewer, token_file: missing.token}\n",
                     {"d.yaml:4: tokens[0].token_file: cannot read '" + (dir_ / "missing.token") + "': no such file"});
  dir_.write("empty.token", "\n");
  expect_token_error("  - {role: viewer, token_file: empty.token}\n",
                     {"d.yaml:4: tokens[0].token_file: '" + (dir_ / "empty.token") + "' is empty"});
  expect_token_error("  - {role: viewer, token_file: .}\n", {"d.yaml:4: tokens[0].token_file:", "is a directory"});
  ::unsetenv("OMNIVIEW_TEST_UNSET");
  expect_token_error("  - {role: viewer, token_env: OMNIVIEW_TEST_UNSET}\n",
                     {"d.yaml:4: tokens[0].token_env: environment variable 'OMNIVIEW_TEST_UNSET' is not set"});
  ::setenv("OMNIVIEW_TEST_EMPTY", "", 1);
  expect_token_error("  - {role: viewer, token_env: OMNIVIEW_TEST_EMPTY}\n",
                     {"d.yaml:4: tokens[0].token_env: environment variable 'OMNIVIEW_TEST_EMPTY' is empty"});
  ::unsetenv("OMNIVIEW_TEST_EMPTY");
  expect_token_error("  - {token: abc}\n", {"d.yaml:4: tokens[0]: missing required key 'role'"});
  expect_token_error("  - {role: admin, token: abc}\n",
                     {"d.yaml:4: tokens[0].role: unknown role 'admin' (expected viewer or operator)"});
  expect_token_error("  - {role: viewer, tokn: abc}\n", {"d.yaml:4: tokens[0].tokn: unknown key"});
  expect_token_error("  role: viewer\n", {"d.yaml:4: tokens: expected a list"});
}

TEST_F(SecurityConfig, DuplicateTokensAreRefusedWithoutShowingThem) {
  dir_.write("op.token", "same-secret\n");
  try {
    parse(std::string(kSources) + "tokens:\n  - {role: viewer, token: same-secret}\n"
                                  "  - {role: operator, token_file: op.token}\n");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("d.yaml:5: tokens[1]: the same token as tokens[0]"), std::string::npos) << what;
    EXPECT_EQ(what.find("same-secret"), std::string::npos) << what;
  }
}

TEST_F(SecurityConfig, Roles) {
  EXPECT_EQ(role_from_string("viewer"), Role::kViewer);
  EXPECT_EQ(role_from_string("operator"), Role::kOperator);
  EXPECT_THROW(role_from_string("Operator"), std::invalid_argument);
  EXPECT_EQ(to_string(Role::kViewer), "viewer");
  EXPECT_EQ(to_string(Role::kOperator), "operator");
  EXPECT_TRUE(role_allows(Role::kOperator, Role::kOperator));
  EXPECT_TRUE(role_allows(Role::kOperator, Role::kViewer));
  EXPECT_TRUE(role_allows(Role::kViewer, Role::kViewer));
  EXPECT_FALSE(role_allows(Role::kViewer, Role::kOperator));
}

TEST_F(SecurityConfig, TlsFilesMustBeReadable) {
  write_certificates();
  const std::string base = std::string(kSources) + "tls:\n";  // tls keys from line 4
  auto config = parse(base + "  cert: s.crt\n  key: s.key\n");
  ASSERT_TRUE(config.tls);
  EXPECT_EQ(config.tls->cert_file, dir_ / "s.crt");
  EXPECT_EQ(config.tls->key_file, dir_ / "s.key");
  EXPECT_TRUE(config.tls->client_ca_file.empty());
  config = parse(base + "  cert: s.crt\n  key: " + (dir_ / "s.key") + "\n  client_ca: ca.crt\n");
  EXPECT_EQ(config.tls->client_ca_file, dir_ / "ca.crt");

  expect_error(base + "  cert: none.crt\n  key: s.key\n",
               {"d.yaml:4: tls.cert: cannot read '" + (dir_ / "none.crt") + "': no such file"});
  expect_error(base + "  cert: s.crt\n  key: none.key\n", {"d.yaml:5: tls.key: cannot read", "none.key"});
  expect_error(base + "  cert: s.crt\n  key: s.key\n  client_ca: none.crt\n",
               {"d.yaml:6: tls.client_ca: cannot read", "none.crt': no such file"});
  expect_error(base + "  cert: s.crt\n", {"d.yaml:4: tls: missing required key 'key'"});
  expect_error(base + "  cert: s.crt\n  key: .\n", {"d.yaml:5: tls.key:", "is a directory"});
  expect_error(base + "  cert: s.crt\n  key: s.key\n  ca: ca.crt\n", {"d.yaml:6: tls.ca: unknown key", "client_ca"});
}

TEST_F(SecurityConfig, TlsFilesAreCheckedWhenTheConfigLoads) {
  write_certificates();
  dir_.write("text.crt", "not a certificate\n");
  const std::string base = std::string(kSources) + "tls:\n";  // tls keys from line 4
  // A key from another pair: named at tls.key, with both files.
  expect_error(base + "  cert: s.crt\n  key: other/server.key\n",
               {"d.yaml:5: tls.key: the private key in '" + (dir_ / "other/server.key") +
                    "' does not belong to the certificate in '" + (dir_ / "s.crt") + "'"});
  // Swapped: the first file read names the config line and says what happened.
  expect_error(base + "  cert: s.key\n  key: s.crt\n",
               {"d.yaml:4: tls.cert:", "holds no PEM certificate", "are tls.cert and tls.key swapped?"});
  expect_error(base + "  cert: s.crt\n  key: ca.crt\n",
               {"d.yaml:5: tls.key:", "holds no unencrypted PEM private key", "swapped?"});
  expect_error(base + "  cert: text.crt\n  key: s.key\n", {"d.yaml:4: tls.cert:", "text.crt' holds no PEM certificate"});
  expect_error(base + "  cert: s.crt\n  key: s.key\n  client_ca: ca.key\n",
               {"d.yaml:6: tls.client_ca:", "holds no PEM certificate", "never belongs in tls.client_ca"});
}

TEST_F(SecurityConfig, RemoteListenNeedsTlsAndTokensOrAnExplicitOptOut) {
  write_certificates();
  const std::string remote = std::string(kSources) + "listen: 0.0.0.0:50051\n";  // line 3
  const std::string tls = "tls: {cert: s.crt, key: s.key}\n";
  const std::string tokens = "tokens: [{role: viewer, token: abc}]\n";
  expect_error(remote, {"d.yaml:3: listen: '0.0.0.0:50051' is reachable from other machines",
                        "neither tls nor tokens", "allow_insecure_remote: true"});
  expect_error(remote + tokens, {"d.yaml:3: listen:", "no tls", "plaintext", "allow_insecure_remote"});
  expect_error(remote + tls, {"d.yaml:3: listen:", "no tokens", "allow_insecure_remote"});
  EXPECT_NO_THROW(parse(remote + tls + tokens));
  EXPECT_NO_THROW(parse(remote + "allow_insecure_remote: true\n"));
  EXPECT_NO_THROW(parse(std::string(kSources) + "listen: localhost:50051\n"));
  // /tmp lets every user in: a socket there needs the same guards as a network address.
  expect_error(std::string(kSources) + "listen: unix:/tmp/omniview.sock\n",
               {"d.yaml:3: listen:", "folder '/tmp'", "every user of this machine can enter", "chmod o-rwx"});
  std::filesystem::permissions(dir_.path(), std::filesystem::perms::others_all, std::filesystem::perm_options::remove);
  EXPECT_NO_THROW(parse(std::string(kSources) + "listen: unix:" + (dir_ / "o.sock") + "\n"));
  // A host name is resolved (here it may resolve to another machine, or not at all: refused either way).
  expect_error(std::string(kSources) + "listen: robot.invalid:50051\n", {"d.yaml:3: listen:", "robot.invalid"});
}

}  // namespace
}  // namespace omniview
