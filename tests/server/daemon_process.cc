#include "daemon_process.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

extern char** environ;

#include "core/map/worker_threads.h"

namespace omniview::testing {

// The test processes honour OMNIVIEW_THREADS as the daemon does (the ThreadSanitizer run
// sets it to 1: TSan cannot see OpenCV's TBB pool hand our lambdas to its workers).
const bool kWorkerThreadsApplied = (apply_worker_threads_from_env(), true);


namespace fs = std::filesystem;

TempDir::TempDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "omniview";
  static int count = 0;  // several in one test must not share a folder
  path_ = fs::temp_directory_path() /
          ("omniview_" + std::to_string(::getpid()) + "_" + name + "_" + std::to_string(count++));
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  if (info && info->result()->Failed()) return;
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::string TempDir::write(const std::string& name, const std::string& text) const {
  const fs::path p = path_ / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p.string();
}

double test_time_scale() {
  const char* text = std::getenv("OMNIVIEW_TEST_TIME_SCALE");
  const double scale = text ? std::atof(text) : 1.0;
  return scale >= 1.0 ? scale : 1.0;
}

int free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t n = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
  ::close(fd);
  return ntohs(a.sin_port);
}

std::string example_dir() { return std::string(OMNIVIEW_SOURCE_DIR) + "/config/examples/dual_fisheye"; }

std::string example_config(double rate_hz, const std::string& extra) {
  std::ostringstream s;
  s << "listen: 127.0.0.1:0\n"
    << "sources:\n"
    << "  - name: examples\n"
    << "    type: images\n"
    << "    rig: " << example_dir() << "/rig.yaml\n"
    << "    images: {front: " << example_dir() << "/front.jpg, back: " << example_dir() << "/back.jpg}\n"
    << "    rate_hz: " << rate_hz << "\n"
    << extra;
  return s.str();
}

ServedProcess::ServedProcess(std::string name, std::vector<std::string> args, fs::path log_file,
                             const fs::path& ready, std::chrono::seconds ready_timeout)
    : name_(std::move(name)), log_file_(std::move(log_file)) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log_file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  const int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + args.front());

  const auto deadline = std::chrono::steady_clock::now() + ready_timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(ready) && fs::file_size(ready) > 0) {
      std::ifstream(ready) >> address_;
      return;
    }
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      ADD_FAILURE() << name_ << " exited before serving:\n" << log();
      throw std::runtime_error(name_ + " did not start");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ADD_FAILURE() << name_ << " not ready within " << ready_timeout.count() << " s:\n" << log();
  throw std::runtime_error(name_ + " did not start");
}

ServedProcess::~ServedProcess() {
  if (pid_ > 0) stop(SIGKILL, std::chrono::seconds(5));
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  if (info && info->result()->Failed()) {
    constexpr size_t kTail = 8000;
    const std::string text = log();
    std::cerr << "---- " << name_ << " output (" << log_file_.string() << ")"
              << (text.size() > kTail ? ", last " + std::to_string(kTail) + " characters" : "") << ":\n"
              << (text.size() > kTail ? text.substr(text.size() - kTail) : text) << "---- end of " << name_
              << " output\n";
  }
}
std::string ServedProcess::log() const {
  std::ifstream in(log_file_);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
long ServedProcess::rss_kb() const {
  std::ifstream in("/proc/" + std::to_string(pid_) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}
int ServedProcess::stop(int sig, std::chrono::seconds timeout) {
  if (pid_ <= 0) return -1;
  kill(pid_, sig);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      if (WIFEXITED(status)) return WEXITSTATUS(status);
      return 128 + WTERMSIG(status);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid_, SIGKILL);
  waitpid(pid_, &status, 0);
  pid_ = -1;
  return -1;
}
namespace {

std::vector<std::string> daemon_args(const TempDir& dir, const std::string& config_text, const std::string& tag,
                                     std::vector<std::string> extra) {
  const std::string config = dir.write("omniviewd_" + tag + ".yaml", config_text);
  std::vector<std::string> args = {OMNIVIEWD, "--config", config, "--ready-file",
                                   (dir.path() / ("ready_" + tag)).string()};
  for (auto& a : extra) args.push_back(std::move(a));
  return args;
}

int next_tag() {
  static int counter = 0;
  return ++counter;
}

}  // namespace

DaemonProcess::DaemonProcess(const TempDir& dir, const std::string& config_text, std::vector<std::string> extra_args)
    : DaemonProcess(dir, config_text, std::move(extra_args), std::to_string(next_tag())) {}

DaemonProcess::DaemonProcess(const TempDir& dir, const std::string& config_text, std::vector<std::string> extra_args,
                             const std::string& tag)
    : ServedProcess("omniviewd", daemon_args(dir, config_text, tag, std::move(extra_args)),
                    dir.path() / ("omniviewd_" + tag + ".log"), dir.path() / ("ready_" + tag)) {}






ProcessResult run_process(const std::string& command_line) {
  ProcessResult r;
  FILE* pipe = popen((command_line + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), pipe)) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::unique_ptr<v1::Omniview::Stub> make_stub(const std::string& address,
                                              std::shared_ptr<grpc::ChannelCredentials> creds) {
  if (!creds) creds = grpc::InsecureChannelCredentials();
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(64 << 20);
  // A connection of its own, like a separate client: by default gRPC shares one connection
  // among channels with equal arguments, and the daemon's per-connection limits would bite.
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  return v1::Omniview::NewStub(grpc::CreateCustomChannel(address, creds, args));
}

std::unique_ptr<grpc::ClientContext> make_context(const std::string& token, std::chrono::milliseconds deadline) {
  auto ctx = std::make_unique<grpc::ClientContext>();
  ctx->set_deadline(std::chrono::system_clock::now() + deadline);
  if (!token.empty()) ctx->AddMetadata("authorization", "Bearer " + token);
  return ctx;
}

}  // namespace omniview::testing
