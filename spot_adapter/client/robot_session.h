// A logged-in session with one robot: the token (refreshed before it expires), the
// directory (service name -> authority) and the robot's identity. Not thread-safe except
// cancel(): the Spot source drives it from its one thread.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <grpcpp/channel.h>
#include <grpcpp/client_context.h>

#include "bosdyn/api/header.pb.h"
#include "spot_adapter/client/robot_channels.h"
#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {

struct SessionOptions {
  std::string credentials_file;  // empty: the BOSDYN_CLIENT_* environment variables
  std::chrono::milliseconds call_timeout{2000};
  std::string client_name = "omniviewd";
};

class RobotSession {
 public:
  RobotSession(RobotChannels& channels, SessionOptions options);

  // Logs in with the credentials, reads the robot's id and its directory. Throws SpotError.
  void connect();
  bool connected() const { return !token_.empty(); }
  // Forgets token and directory and drops the channels (the robot went away).
  void disconnect();
  // Exchanges the token for a fresh one when it is due (hourly, or at 80 % of its
  // lifetime when that is shorter); falls back to a new login if the robot refuses.
  void refresh_if_due();

  // The channel of directory service `service` ("image", "robot-state"); throws
  // SpotError(kProtocol) naming the services the robot has when it lacks this one.
  std::shared_ptr<grpc::Channel> service_channel(const std::string& service) const;

  // One unary call to directory service `service` with a request header, the token, the
  // call timeout and cancel() wired up, e.g.
  //   call("robot-state", &api::RobotStateService::Stub::GetRobotState, request, "GetRobotState").
  // Throws SpotError naming `what` for a failed call or an error in the response header.
  template <class Stub, class Request, class Response>
  Response call(const std::string& service,
                grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Response*), Request request,
                const std::string& what);

  // Sets the deadline and, with `authorised`, the bearer token on `context`, and lets
  // cancel() abort the call. Pair with CallScope.
  void prepare(grpc::ClientContext& context, bool authorised, std::chrono::milliseconds timeout = {}) const;
  bosdyn::api::RequestHeader request_header() const;

  // "spot-mock (serial BD-0000, software 4.0.0)", once connected.
  const std::string& robot() const { return robot_; }

  // Aborts the call in flight and every later one (the daemon is stopping). Thread-safe.
  void cancel();
  bool cancelled() const;

  // Registers `context` as the call in flight for cancel(); unregisters when destroyed.
  class CallScope {
   public:
    CallScope(const RobotSession& session, grpc::ClientContext& context);
    ~CallScope();
    CallScope(const CallScope&) = delete;
    CallScope& operator=(const CallScope&) = delete;

   private:
    const RobotSession& session_;
  };

 private:
  void login();
  void read_robot_id();
  void read_directory();
  void set_token(const std::string& token);

  RobotChannels& channels_;
  SessionOptions options_;
  std::string token_;
  std::chrono::steady_clock::time_point refresh_due_;
  std::map<std::string, std::string> authorities_;  // directory: service name -> authority
  std::string robot_;

  mutable std::mutex cancel_mutex_;
  mutable grpc::ClientContext* in_flight_ = nullptr;
  bool cancelled_ = false;
};

// Throws SpotError(kProtocol) when a response header reports an error. Spot's SDKs treat
// CODE_UNSPECIFIED as an error too: a well-behaved service always sets CODE_OK.
void check_header(const bosdyn::api::ResponseHeader& header, const std::string& what);

// Seconds from issue to expiry of a JWT-shaped token, when its payload says (0: unknown).
double token_lifetime_s(const std::string& token);

template <class Stub, class Request, class Response>
Response RobotSession::call(const std::string& service,
                            grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Response*),
                            Request request, const std::string& what) {
  *request.mutable_header() = request_header();
  Response response;
  grpc::ClientContext context;
  prepare(context, true);
  Stub stub(service_channel(service));
  {
    CallScope scope(*this, context);
    check_status((stub.*method)(&context, request, &response), what);
  }
  check_header(response.header(), what);
  return response;
}

}  // namespace omniview::spot
