// Connection flags, environment variables and the shared argument parsing of client commands.
#include "cli/client/connection.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "cli/client/command_support.h"

namespace omniview::cli {
namespace {

namespace fs = std::filesystem;

class ConnectionFlags : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : {"OMNIVIEW_SERVER", "OMNIVIEW_TOKEN", "OMNIVIEW_TOKEN_FILE"}) unsetenv(name);
    dir_ = fs::temp_directory_path() / ("omniview_conn_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    for (const char* name : {"OMNIVIEW_SERVER", "OMNIVIEW_TOKEN", "OMNIVIEW_TOKEN_FILE"}) unsetenv(name);
    fs::remove_all(dir_);
  }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  static ConnectionOptions parse(const std::vector<std::string>& argv) { return connection_options(Args(argv, {})); }
  fs::path dir_;
};

TEST_F(ConnectionFlags, DefaultsToLoopback) {
  const auto o = parse({});
  EXPECT_EQ(o.server, "127.0.0.1:50051");
  EXPECT_TRUE(o.token.empty());
  EXPECT_TRUE(o.tls_ca_file.empty());
  EXPECT_EQ(o.deadline, std::chrono::milliseconds(10000));
}

TEST_F(ConnectionFlags, FlagBeatsEnvironment) {
  setenv("OMNIVIEW_SERVER", "robot:6000", 1);
  EXPECT_EQ(parse({}).server, "robot:6000");
  EXPECT_EQ(parse({"--server", "other:7000"}).server, "other:7000");
}

TEST_F(ConnectionFlags, RejectsServerWithoutPort) { EXPECT_THROW(parse({"--server", "robot"}), UsageError); }

TEST_F(ConnectionFlags, ReadsTokenFileFirstLineTrimmed) {
  const auto file = write("op.token", "  s3cret \nignored\n");
  const auto o = parse({"--token-file", file});
  EXPECT_EQ(o.token, "s3cret");
  EXPECT_NE(o.token_origin.find("--token-file"), std::string::npos);
}

TEST_F(ConnectionFlags, TokenFromEnvironment) {
  setenv("OMNIVIEW_TOKEN", "envtoken\n", 1);
  EXPECT_EQ(parse({}).token, "envtoken");
  setenv("OMNIVIEW_TOKEN", "", 1);
  setenv("OMNIVIEW_TOKEN_FILE", write("t", "filetoken").c_str(), 1);
  EXPECT_EQ(parse({}).token, "filetoken");
  // The flag wins over both.
  EXPECT_EQ(parse({"--token-file", write("u", "flagtoken")}).token, "flagtoken");
}

TEST_F(ConnectionFlags, MissingOrEmptyTokenFileIsAUsageError) {
  try {
    parse({"--token-file", (dir_ / "nope").string()});
    FAIL();
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("nope"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse({"--token-file", write("empty", "\n\n")}), UsageError);
}

TEST_F(ConnectionFlags, Timeout) {
  EXPECT_EQ(parse({"--timeout", "2.5"}).deadline, std::chrono::milliseconds(2500));
  for (const char* bad : {"0", "-1", "abc", "1s", "nan"}) EXPECT_THROW(parse({"--timeout", bad}), UsageError) << bad;
}

TEST_F(ConnectionFlags, TlsServerNameNeedsCa) {
  EXPECT_THROW(parse({"--tls-server-name", "robot"}), UsageError);
  const auto o = parse({"--tls-ca", "ca.pem", "--tls-server-name", "robot"});
  EXPECT_EQ(o.tls_ca_file, "ca.pem");
  EXPECT_EQ(o.tls_server_name, "robot");
}

TEST_F(ConnectionFlags, ClientCertificateNeedsItsKeyAndACa) {
  EXPECT_THROW(parse({"--tls-ca", "ca.pem", "--tls-cert", "c.pem"}), UsageError);
  EXPECT_THROW(parse({"--tls-ca", "ca.pem", "--tls-key", "k.pem"}), UsageError);
  EXPECT_THROW(parse({"--tls-cert", "c.pem", "--tls-key", "k.pem"}), UsageError);
  const auto o = parse({"--tls-ca", "ca.pem", "--tls-cert", "c.pem", "--tls-key", "k.pem"});
  EXPECT_EQ(o.tls_cert_file, "c.pem");
  EXPECT_EQ(o.tls_key_file, "k.pem");
}

TEST(CommandArgs, ShortFlagsAndHelp) {
  const auto args = parse_command_args({"front", "-o", "out.png", "--gray"}, {"gray"}, {"output"}, "help text");
  ASSERT_TRUE(args);
  EXPECT_EQ(args->get("output"), "out.png");
  EXPECT_TRUE(args->has("gray"));
  ASSERT_EQ(args->positional().size(), 1u);
  EXPECT_FALSE(parse_command_args({"-h"}, {}, {}, ""));
  EXPECT_FALSE(parse_command_args({"front", "--help"}, {}, {}, ""));
}

TEST(CommandArgs, UnknownFlagsAreRejected) {
  try {
    parse_command_args({"front", "--veiw", "x"}, {}, {"output"}, "");
    FAIL();
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--veiw"), std::string::npos);
  }
  EXPECT_THROW(parse_command_args({"front", "-x"}, {}, {}, ""), UsageError);
  // Connection flags are known to every command; negative numbers are values.
  EXPECT_NO_THROW(parse_command_args({"--server", "h:1", "--token-file", "f", "-5"}, {}, {}, ""));
}

TEST(CommandArgs, Numbers) {
  EXPECT_EQ(parse_count("12", "--frames"), 12);
  for (const char* bad : {"0", "-3", "1.5", "x", ""}) EXPECT_THROW(parse_count(bad, "--frames"), UsageError) << bad;
  EXPECT_DOUBLE_EQ(parse_positive("0.25", "--rate"), 0.25);
  EXPECT_THROW(parse_positive("0", "--rate"), UsageError);
}

}  // namespace
}  // namespace omniview::cli

namespace omniview::cli {
namespace {

TEST(Connection, RejectsACaFileWithoutCertificates) {
  const auto path = std::filesystem::temp_directory_path() / ("omniview_ca_" + std::to_string(::getpid()));
  std::ofstream(path) << "not a certificate\n";
  ConnectionOptions options;
  options.tls_ca_file = path.string();
  EXPECT_THROW(Connection{options}, UsageError);
  options.tls_ca_file = (path.string() + ".missing");
  EXPECT_THROW(Connection{options}, UsageError);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace omniview::cli
