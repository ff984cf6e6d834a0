// What can go wrong talking to a robot, sorted by what the caller should do about it.
#pragma once

#include <stdexcept>
#include <string>

#include <grpcpp/support/status.h>

namespace omniview::spot {

class SpotError : public std::runtime_error {
 public:
  enum class Kind {
    kUnreachable,    // network, TLS, robot away: retry soon with backoff
    kTokenRejected,  // our token is no longer accepted (expired, robot rebooted): log in again
    kLoginRefused,   // wrong username or password: retry rarely (the robot locks out after 6)
    kLockedOut,      // too many bad logins: wait out the lock
    kCredentials,    // our own credentials file or environment is unusable
    kProtocol,       // the robot answered with something we cannot use
  };

  SpotError(Kind kind, const std::string& message, grpc::StatusCode code = grpc::StatusCode::UNKNOWN)
      : std::runtime_error(message), kind_(kind), code_(code) {}
  Kind kind() const { return kind_; }
  // The failed call's gRPC code (UNKNOWN for errors that were not a call's).
  grpc::StatusCode code() const { return code_; }

 private:
  Kind kind_;
  grpc::StatusCode code_;
};

// Throws SpotError for a failed call: `what` says which call ("GetImage on api.spot.robot").
void check_status(const grpc::Status& status, const std::string& what);

}  // namespace omniview::spot
