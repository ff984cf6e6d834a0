// The real spot-mock, started as a separate process on a free loopback port, and TLS
// clients that reach it as a Spot client reaches a robot (one channel per authority,
// trusting the mock's CA). For the mock's own tests and for integration tests that put the
// daemon in front of it.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>

namespace omniview::testing {

class SpotMockProcess {
 public:
  // Starts spot-mock with --port 0, its certificates in `dir`/certs and its login in
  // `dir`/credentials.yaml (made by the mock unless they exist), plus `extra_args`; waits
  // until it serves. Fails the test (and throws) if it exits or is not ready within 60 s.
  SpotMockProcess(const std::filesystem::path& dir, std::vector<std::string> extra_args = {});
  ~SpotMockProcess();  // kills it if still running

  const std::string& address() const { return address_; }  // 127.0.0.1:PORT
  int port() const;
  pid_t pid() const { return pid_; }
  std::string certs_dir() const { return (dir_ / "certs").string(); }
  std::string credentials_file() const { return (dir_ / "credentials.yaml").string(); }
  std::string username() const;
  std::string password() const;
  std::string log() const;  // its stdout and stderr so far

  // Sends `sig` and waits up to `timeout`; returns the exit code (-1: killed after the
  // timeout; 128+n: killed by signal n).
  int stop(int sig = 15, std::chrono::seconds timeout = std::chrono::seconds(10));

  // A TLS channel to `authority` (api.spot.robot, auth.spot.robot, id.spot.robot) that trusts
  // only the mock's CA; a connection of its own.
  std::shared_ptr<grpc::Channel> channel(const std::string& authority) const;

  // Logs in with the mock's credentials on auth.spot.robot; fails the test if refused.
  std::string login() const;

  // Runs `spot-mock control --port P --certs DIR <args>`: exit code and output.
  struct Output {
    int exit_code = -1;
    std::string text;
  };
  Output control(const std::string& args) const;

 private:
  std::filesystem::path dir_;
  std::filesystem::path log_file_;
  std::string address_;
  pid_t pid_ = -1;
};

// A context with a deadline and, unless `token` is empty, `authorization: Bearer <token>`.
std::unique_ptr<grpc::ClientContext> spot_context(const std::string& token = "",
                                                  std::chrono::milliseconds deadline = std::chrono::seconds(10));

}  // namespace omniview::testing
