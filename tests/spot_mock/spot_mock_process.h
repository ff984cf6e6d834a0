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

#include "tests/server/daemon_process.h"

namespace omniview::testing {

class SpotMockProcess : public ServedProcess {
 public:
  // Starts spot-mock on `port` (0: a free one), its certificates in `dir`/certs and its
  // login in `dir`/credentials.yaml (made by the mock unless they exist: a mock started
  // again in the same folder is the same robot), plus `extra_args`; waits until it serves.
  // Fails the test (and throws) if it exits or is not ready within 60 s (the start-up
  // render is slow under the sanitizers).
  SpotMockProcess(const std::filesystem::path& dir, std::vector<std::string> extra_args = {}, int port = 0);

  int port() const;
  std::string certs_dir() const { return certs_dir(dir_); }
  static std::string certs_dir(const std::filesystem::path& dir) { return (dir / "certs").string(); }
  std::string credentials_file() const { return (dir_ / "credentials.yaml").string(); }
  std::string username() const;
  std::string password() const;

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
  // One of `control --counters`' counters (e.g. "get_point_cloud_calls"); fails the test
  // and returns -1 when there is no such counter.
  double counter(const std::string& name) const;

 private:
  SpotMockProcess(const std::filesystem::path& dir, std::vector<std::string> extra_args, int port,
                  const std::string& tag);
  std::filesystem::path dir_;
};

// A context with a deadline and, unless `token` is empty, `authorization: Bearer <token>`.
std::unique_ptr<grpc::ClientContext> spot_context(const std::string& token = "",
                                                  std::chrono::milliseconds deadline = std::chrono::seconds(10));

}  // namespace omniview::testing
