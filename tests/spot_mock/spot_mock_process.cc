#include "tests/spot_mock/spot_mock_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <fstream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "bosdyn/api/auth_service.grpc.pb.h"
#include "spot_adapter/mock/auth/certificates.h"
#include "spot_adapter/mock/auth/credentials.h"
#include "tests/server/daemon_process.h"

extern char** environ;

namespace omniview::testing {
namespace fs = std::filesystem;

SpotMockProcess::SpotMockProcess(const fs::path& dir, std::vector<std::string> extra_args) : dir_(dir) {
  static int counter = 0;
  const std::string tag = std::to_string(++counter);
  const fs::path ready = dir / ("spot_mock_ready_" + tag);
  log_file_ = dir / ("spot_mock_" + tag + ".log");
  std::vector<std::string> args = {SPOT_MOCK,       "--port",        "0", "--certs", certs_dir(), "--credentials",
                                   credentials_file(), "--ready-file", ready.string()};
  for (auto& a : extra_args) args.push_back(std::move(a));
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log_file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  const int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + std::string(SPOT_MOCK));

  // Generous: the start-up render is slow under the sanitizers.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(ready)) {
      std::ifstream(ready) >> address_;
      return;
    }
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      ADD_FAILURE() << "spot-mock exited before serving:\n" << log();
      throw std::runtime_error("spot-mock did not start");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ADD_FAILURE() << "spot-mock not ready within 60 s:\n" << log();
  throw std::runtime_error("spot-mock did not start");
}

SpotMockProcess::~SpotMockProcess() {
  if (pid_ > 0) stop(SIGKILL, std::chrono::seconds(5));
}

int SpotMockProcess::port() const { return std::stoi(address_.substr(address_.rfind(':') + 1)); }

std::string SpotMockProcess::username() const { return spot_mock::load_or_create_credentials(credentials_file()).username; }
std::string SpotMockProcess::password() const { return spot_mock::load_or_create_credentials(credentials_file()).password; }

std::string SpotMockProcess::log() const {
  std::ifstream in(log_file_);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

int SpotMockProcess::stop(int sig, std::chrono::seconds timeout) {
  if (pid_ <= 0) return -1;
  kill(pid_, sig);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid_, SIGKILL);
  waitpid(pid_, &status, 0);
  pid_ = -1;
  return -1;
}

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
  return grpc::CreateCustomChannel(address_, grpc::SslCredentials(tls), args);
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

std::unique_ptr<grpc::ClientContext> spot_context(const std::string& token, std::chrono::milliseconds deadline) {
  auto ctx = std::make_unique<grpc::ClientContext>();
  ctx->set_deadline(std::chrono::system_clock::now() + deadline);
  if (!token.empty()) ctx->AddMetadata("authorization", "Bearer " + token);
  return ctx;
}

}  // namespace omniview::testing
