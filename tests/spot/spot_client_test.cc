// The Spot client's small parts: robot addresses, tokens, credentials and the source's
// config keys (every error names the file, line and key, and never a password).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/io/yaml_reader.h"
#include "spot_adapter/client/credentials.h"
#include "spot_adapter/client/robot_channels.h"
#include "spot_adapter/client/robot_session.h"
#include "spot_adapter/client/spot_error.h"
#include "spot_adapter/source/spot_settings.h"

namespace omniview::spot {
namespace {

namespace fs = std::filesystem;

class TempFolder {
 public:
  TempFolder() : path_(fs::temp_directory_path() / ("spot_client_test_" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~TempFolder() { fs::remove_all(path_); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return (path_ / name).string();
  }
  std::string path() const { return path_.string(); }

 private:
  fs::path path_;
};

TEST(RobotAddress, HostPortAndIpv6) {
  EXPECT_EQ(to_string(parse_robot_address("192.168.80.3")), "192.168.80.3:443");
  EXPECT_EQ(parse_robot_address("127.0.0.1:50443").port, 50443);
  EXPECT_EQ(parse_robot_address("[fe80::1]:444").host, "fe80::1");
  EXPECT_EQ(to_string(parse_robot_address("[fe80::1]")), "[fe80::1]:443");
  EXPECT_THROW(parse_robot_address(""), std::invalid_argument);
  EXPECT_THROW(parse_robot_address("spot:99999"), std::invalid_argument);
  EXPECT_THROW(parse_robot_address("spot:http"), std::invalid_argument);
  try {
    parse_robot_address("https://10.0.0.3");
    ADD_FAILURE() << "a URL is no address";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("without a scheme"), std::string::npos) << e.what();
  }
  EXPECT_EQ(full_authority("image"), "image.spot.robot");
  EXPECT_EQ(full_authority("api.spot.robot"), "api.spot.robot");
}

TEST(Token, LifetimeFromAJwtPayload) {
  // {"exp":1700043200,"iat":1700000000} base64url-encoded, between a header and a signature.
  EXPECT_DOUBLE_EQ(token_lifetime_s("eyJhbGciOiJIUzI1NiJ9.eyJleHAiOjE3MDAwNDMyMDAsImlhdCI6MTcwMDAwMDAwMH0.c2ln"),
                   43200);
  EXPECT_EQ(token_lifetime_s("opaque-token"), 0);
  EXPECT_EQ(token_lifetime_s("a.!!!.b"), 0);
}

TEST(Credentials, FromFileOrEnvironmentNeverQuotingThePassword) {
  TempFolder dir;
  const auto file = dir.write("cred.yaml", "username: admin\npassword: s3cret\n");
  const Credentials c = load_credentials(file);
  EXPECT_EQ(c.username, "admin");
  EXPECT_EQ(c.password, "s3cret");

  const auto bad = dir.write("bad.yaml", "username: admin\npassword: [s3cret\n");
  try {
    load_credentials(bad);
    FAIL() << "bad YAML accepted";
  } catch (const SpotError& e) {
    EXPECT_EQ(e.kind(), SpotError::Kind::kCredentials);
    EXPECT_EQ(std::string(e.what()).find("s3cret"), std::string::npos) << e.what();
  }
  const auto no_password = dir.write("nopw.yaml", "username: admin\n");
  EXPECT_THROW(load_credentials(no_password), SpotError);
  EXPECT_THROW(load_credentials(dir.path() + "/missing.yaml"), SpotError);

  ::setenv(kUsernameEnv, "envuser", 1);
  ::setenv(kPasswordEnv, "envpw", 1);
  EXPECT_EQ(load_credentials("").username, "envuser");
  ::unsetenv(kUsernameEnv);
  ::unsetenv(kPasswordEnv);
  EXPECT_THROW(load_credentials(""), SpotError);
}

std::string settings_error(const std::string& yaml, const std::string& folder) {
  const auto reader = YamlReader::from_string(yaml, "spot.yaml");
  SourceConfig config;
  config.name = "spot";
  config.reader = &reader;
  config.node = reader.root();
  config.path = "sources[0]";
  config.folder = folder;
  try {
    parse_spot_settings(config);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SpotSettings, DefaultsAndClearErrors) {
  TempFolder dir;
  dir.write("ca.pem", "-----BEGIN CERTIFICATE-----\nMIIB\n-----END CERTIFICATE-----\n");
  dir.write("cred.yaml", "username: u\npassword: p\n");
  const std::string base = "type: spot\nrobot: 127.0.0.1:50443\nca_file: ca.pem\ncredentials_file: cred.yaml\n";
  {
    const auto reader = YamlReader::from_string(base, "spot.yaml");
    SourceConfig config{"spot", &reader, reader.root(), "sources[0]", dir.path()};
    const SpotSettings s = parse_spot_settings(config);
    EXPECT_EQ(s.cameras, default_body_cameras());
    EXPECT_EQ(s.address.port, 50443);
    EXPECT_DOUBLE_EQ(s.rate_hz, 15);
    EXPECT_TRUE(s.jpeg);
  }
  EXPECT_EQ(settings_error(base, dir.path()), "(no error)");
  EXPECT_NE(settings_error(base + "rate_hz: 60\n", dir.path()).find("spot.yaml:5"), std::string::npos);
  EXPECT_NE(settings_error(base + "pixel_format: bgr\n", dir.path()).find("not one of: greyscale, grayscale, rgb"),
            std::string::npos);
  EXPECT_NE(settings_error(base + "camera: [x]\n", dir.path()).find("camera"), std::string::npos);
  EXPECT_NE(settings_error(base + "cameras: [a, a]\n", dir.path()).find("listed twice"), std::string::npos);
  const std::string no_ca = "type: spot\nrobot: spot\nca_file: nope.pem\ncredentials_file: cred.yaml\n";
  EXPECT_NE(settings_error(no_ca, dir.path()).find("spot.yaml:3"), std::string::npos);
  const std::string no_cred = "type: spot\nrobot: spot\nca_file: ca.pem\n";
  ::unsetenv(kUsernameEnv);
  EXPECT_NE(settings_error(no_cred, dir.path()).find("BOSDYN_CLIENT_USERNAME"), std::string::npos);
  EXPECT_NE(settings_error("type: spot\nrobot: 'spot:x'\nca_file: ca.pem\n", dir.path()).find("spot.yaml:2"),
            std::string::npos);
}

}  // namespace
}  // namespace omniview::spot
