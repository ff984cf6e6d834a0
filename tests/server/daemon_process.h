// The real omniviewd, started as a separate process on a free loopback port, for tests.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <grpcpp/grpcpp.h>

#include "omniview/v1/omniview.grpc.pb.h"

namespace omniview::testing {

// A scratch folder removed at the end (unless the test failed: then it is kept for a look).
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::string write(const std::string& name, const std::string& text) const;  // returns the full path

 private:
  std::filesystem::path path_;
};

// How much slower than a release build the processes under test run: OMNIVIEW_TEST_TIME_SCALE
// (scripts/test.sh sets it for the sanitizer builds), 1 when unset. Bounds that time the
// product ("views resume within 2 s") are multiplied by it, so a sanitizer run still checks
// the code path without failing on the sanitizer's own slowdown.
double test_time_scale();

// `t` times test_time_scale().
inline std::chrono::milliseconds time_scaled(std::chrono::milliseconds t) {
  return std::chrono::milliseconds(static_cast<int64_t>(t.count() * test_time_scale()));
}

// Polls `done` every 50 ms until it holds or time_scaled(`timeout`) has passed; its last answer.
template <typename F>
bool eventually_within(F&& done, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + time_scaled(timeout);
  while (std::chrono::steady_clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return done();
}

// A TCP port on 127.0.0.1 that was free a moment ago (for a second server a test starts on
// a port it must know beforehand; another process may still take it in between).
int free_port();

// Where the bundled example rig and images are (absolute).
std::string example_dir();

// A config serving the bundled dual-fisheye example as source `examples` (images at
// `rate_hz`), listening on a free loopback port, followed by `extra` YAML (views, tokens...).
std::string example_config(double rate_hz = 30, const std::string& extra = "");

// A server program started as a child process, its output in `log_file`, that writes the
// address it serves on into `ready_file` once serving (omniviewd, spot-mock).
class ServedProcess {
 public:
  // `args`: the program and its arguments. Waits until `ready_file` appears; fails the test
  // (and throws) if the program exits first or is not ready within `ready_timeout`.
  ServedProcess(std::string name, std::vector<std::string> args, std::filesystem::path log_file,
                const std::filesystem::path& ready_file,
                std::chrono::seconds ready_timeout = std::chrono::seconds(20));
  // Prints the end of the program's output when the test failed (CI shows nothing else).
  ~ServedProcess();
  ServedProcess(const ServedProcess&) = delete;
  ServedProcess& operator=(const ServedProcess&) = delete;

  const std::string& address() const { return address_; }
  pid_t pid() const { return pid_; }
  std::string log() const;
  long rss_kb() const;  // resident memory, from /proc

  // Sends `sig` and waits up to `timeout` for the exit; returns the exit code (-1: it did
  // not exit in time and was killed; 128+n: killed by signal n).
  int stop(int sig = 15, std::chrono::seconds timeout = std::chrono::seconds(10));

 private:
  std::string name_;
  std::filesystem::path log_file_;
  std::string address_;
  pid_t pid_ = -1;
};

class DaemonProcess : public ServedProcess {
 public:
  // Starts omniviewd with `config_text` (written into `dir`) and waits until it serves.
  DaemonProcess(const TempDir& dir, const std::string& config_text, std::vector<std::string> extra_args = {});

 private:
  DaemonProcess(const TempDir& dir, const std::string& config_text, std::vector<std::string> extra_args,
                const std::string& tag);
};

// Runs omniviewd to completion (config errors, --check, --help): exit code and output.
struct ProcessResult {
  int exit_code = -1;
  std::string output;
};
ProcessResult run_process(const std::string& command_line);

std::unique_ptr<v1::Omniview::Stub> make_stub(const std::string& address,
                                              std::shared_ptr<grpc::ChannelCredentials> creds = nullptr);
// A context with a 10 s deadline and, if `token` is not empty, the bearer token.
std::unique_ptr<grpc::ClientContext> make_context(const std::string& token = "",
                                                  std::chrono::milliseconds deadline = std::chrono::seconds(10));

}  // namespace omniview::testing
