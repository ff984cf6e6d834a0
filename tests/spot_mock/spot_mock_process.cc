#include "tests/spot_mock/spot_mock_process.h"


#include <algorithm>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "bosdyn/api/auth_service.grpc.pb.h"
#include "spot_adapter/mock/auth/certificates.h"
#include "spot_adapter/mock/auth/credentials.h"
#include "tests/server/daemon_process.h"

namespace omniview::testing {
namespace fs = std::filesystem;

namespace {

std::vector<std::string> mock_args(const fs::path& dir, std::vector<std::string> extra, int port, const std::string& tag) {
  std::vector<std::string> args = {SPOT_MOCK, "--port", std::to_string(port), "--certs", SpotMockProcess::certs_dir(dir),
                                   "--credentials", (dir / "credentials.yaml").string(), "--ready-file",
                                   (dir / ("spot_mock_ready_" + tag)).string()};
  if (std::find(extra.begin(), extra.end(), "--render-cache") == extra.end()) {
    args.insert(args.end(), {"--render-cache", SPOT_MOCK_RENDER_CACHE});
  }
  for (auto& a : extra) args.push_back(std::move(a));
  return args;
}

int next_tag() {
  static int counter = 0;
  return ++counter;
}

}  // namespace

SpotMockProcess::SpotMockProcess(const fs::path& dir, std::vector<std::string> extra_args, int port)
    : SpotMockProcess(dir, std::move(extra_args), port, std::to_string(next_tag())) {}

SpotMockProcess::SpotMockProcess(const fs::path& dir, std::vector<std::string> extra_args, int port,
                                 const std::string& tag)
    : ServedProcess("spot-mock", mock_args(dir, std::move(extra_args), port, tag), dir / ("spot_mock_" + tag + ".log"),
                    dir / ("spot_mock_ready_" + tag), std::chrono::seconds(60)),
      dir_(dir) {}

int SpotMockProcess::port() const { return std::stoi(address().substr(address().rfind(':') + 1)); }

std::string SpotMockProcess::username() const { return spot_mock::load_or_create_credentials(credentials_file()).username; }
std::string SpotMockProcess::password() const { return spot_mock::load_or_create_credentials(credentials_file()).password; }

std::shared_ptr<grpc::Channel> SpotMockProcess::channel(const std::string& authority) const {
  std::ifstream in(spot_mock::ca_cert_file(certs_dir()));
  std::stringstream ca;
  ca << in.rdbuf();
  grpc::SslCredentialsOptions tls;
  tls.pem_root_certs = ca.str();
  grpc::ChannelArguments args;
  args.SetSslTargetNameOverride(authority);
  args.SetMaxReceiveMessageSize(100 << 20);
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  return grpc::CreateCustomChannel(address(), grpc::SslCredentials(tls), args);
}

std::string SpotMockProcess::login() const {
  auto stub = bosdyn::api::AuthService::NewStub(channel("auth.spot.robot"));
  bosdyn::api::GetAuthTokenRequest request;
  request.set_username(username());
  request.set_password(password());
  bosdyn::api::GetAuthTokenResponse response;
  const grpc::Status status = stub->GetAuthToken(spot_context().get(), request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(response.status(), bosdyn::api::GetAuthTokenResponse::STATUS_OK);
  return response.token();
}

SpotMockProcess::Output SpotMockProcess::control(const std::string& args) const {
  const ProcessResult r = run_process(std::string(SPOT_MOCK) + " control --port " + std::to_string(port()) +
                                      " --certs " + certs_dir() + " " + args);
  return {r.exit_code, r.output};
}

double SpotMockProcess::counter(const std::string& name) const {
  const Output r = control("--counters");
  EXPECT_EQ(r.exit_code, 0) << r.text;
  std::istringstream lines(r.text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(name + "=", 0) == 0) return std::stod(line.substr(name.size() + 1));
  }
  ADD_FAILURE() << "no " << name << " in:\n" << r.text;
  return -1;
}

std::unique_ptr<grpc::ClientContext> spot_context(const std::string& token, std::chrono::milliseconds deadline) {
  auto ctx = std::make_unique<grpc::ClientContext>();
  ctx->set_deadline(std::chrono::system_clock::now() + deadline);
  if (!token.empty()) ctx->AddMetadata("authorization", "Bearer " + token);
  return ctx;
}

}  // namespace omniview::testing
