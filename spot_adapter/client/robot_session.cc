#include "spot_adapter/client/robot_session.h"

#include <algorithm>

#include <google/protobuf/util/time_util.h>
#include <yaml-cpp/yaml.h>

#include "bosdyn/api/auth_service.grpc.pb.h"
#include "bosdyn/api/directory_service.grpc.pb.h"
#include "bosdyn/api/robot_id_service.grpc.pb.h"
#include "spot_adapter/client/credentials.h"
#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {
namespace {

using Clock = std::chrono::steady_clock;
namespace api = bosdyn::api;

constexpr const char* kAuthAuthority = "auth";       // bootstrap authorities: known before
constexpr const char* kDirectoryAuthority = "api";   // the directory can be read
constexpr const char* kRobotIdAuthority = "id";
constexpr auto kMaxRefreshInterval = std::chrono::hours(1);

std::string base64url_decode(const std::string& in) {
  std::string out;
  unsigned buffer = 0;
  int bits = 0;
  for (char c : in) {
    int v;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '-' || c == '+') v = 62;
    else if (c == '_' || c == '/') v = 63;
    else if (c == '=') break;
    else return {};
    buffer = (buffer << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((buffer >> bits) & 0xFF));
    }
  }
  return out;
}

}  // namespace

void check_header(const api::ResponseHeader& header, const std::string& what) {
  if (header.error().code() == api::CommonError::CODE_OK) return;
  const std::string code = api::CommonError::Code_Name(header.error().code());
  throw SpotError(SpotError::Kind::kProtocol,
                  what + ": the robot reports " + code +
                      (header.error().message().empty() ? "" : ": " + header.error().message()));
}

double token_lifetime_s(const std::string& token) {
  const auto first = token.find('.');
  const auto second = token.find('.', first + 1);
  if (first == std::string::npos || second == std::string::npos) return 0;
  try {
    const YAML::Node payload = YAML::Load(base64url_decode(token.substr(first + 1, second - first - 1)));
    if (!payload.IsMap() || !payload["exp"] || !payload["iat"]) return 0;
    return payload["exp"].as<double>() - payload["iat"].as<double>();
  } catch (const YAML::Exception&) {
    return 0;
  }
}

RobotSession::RobotSession(RobotChannels& channels, SessionOptions options)
    : channels_(channels), options_(std::move(options)) {}

RobotSession::CallScope::CallScope(const RobotSession& session, grpc::ClientContext& context) : session_(session) {
  std::lock_guard lock(session.cancel_mutex_);
  if (session.cancelled_) context.TryCancel();
  session.in_flight_ = &context;
}

RobotSession::CallScope::~CallScope() {
  std::lock_guard lock(session_.cancel_mutex_);
  session_.in_flight_ = nullptr;
}

void RobotSession::cancel() {
  std::lock_guard lock(cancel_mutex_);
  cancelled_ = true;
  if (in_flight_) in_flight_->TryCancel();
}

bool RobotSession::cancelled() const {
  std::lock_guard lock(cancel_mutex_);
  return cancelled_;
}

void RobotSession::prepare(grpc::ClientContext& context, bool authorised, std::chrono::milliseconds timeout) const {
  context.set_deadline(std::chrono::system_clock::now() +
                       (timeout.count() > 0 ? timeout : options_.call_timeout));
  if (authorised) context.AddMetadata("authorization", "Bearer " + token_);
}

api::RequestHeader RobotSession::request_header() const {
  api::RequestHeader h;
  *h.mutable_request_timestamp() = google::protobuf::util::TimeUtil::GetCurrentTime();
  h.set_client_name(options_.client_name);
  return h;
}

void RobotSession::connect() {
  token_.clear();
  login();
  read_robot_id();
  read_directory();
}

void RobotSession::disconnect() {
  token_.clear();
  authorities_.clear();
  channels_.reset();
}

void RobotSession::set_token(const std::string& token) {
  if (token.empty()) throw SpotError(SpotError::Kind::kProtocol, "the robot's auth service returned an empty token");
  token_ = token;
  auto interval = std::chrono::duration_cast<Clock::duration>(kMaxRefreshInterval);
  if (const double life = token_lifetime_s(token); life > 0) {
    interval = std::min(interval, std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(0.8 * life)));
  }
  refresh_due_ = Clock::now() + interval;
}

void RobotSession::login() {
  const Credentials credentials = load_credentials(options_.credentials_file);
  api::GetAuthTokenRequest request;
  *request.mutable_header() = request_header();
  request.set_username(credentials.username);
  request.set_password(credentials.password);
  api::GetAuthTokenResponse response;
  grpc::ClientContext context;
  prepare(context, false, std::max(options_.call_timeout, std::chrono::milliseconds(5000)));
  const auto stub = api::AuthService::NewStub(channels_.channel(kAuthAuthority));
  {
    CallScope scope(*this, context);
    check_status(stub->GetAuthToken(&context, request, &response), "login (GetAuthToken on auth.spot.robot)");
  }
  switch (response.status()) {
    case api::GetAuthTokenResponse::STATUS_OK:
      check_header(response.header(), "login");
      set_token(response.token());
      return;
    case api::GetAuthTokenResponse::STATUS_INVALID_LOGIN:
      throw SpotError(SpotError::Kind::kLoginRefused,
                      "login refused for user '" + credentials.username + "': wrong username or password");
    case api::GetAuthTokenResponse::STATUS_TEMPORARILY_LOCKED_OUT:
      throw SpotError(SpotError::Kind::kLockedOut, "login for user '" + credentials.username +
                                                       "' is locked after too many failed attempts");
    default:
      throw SpotError(SpotError::Kind::kProtocol,
                      "login answered " + api::GetAuthTokenResponse::Status_Name(response.status()));
  }
}

void RobotSession::refresh_if_due() {
  if (!connected() || Clock::now() < refresh_due_) return;
  api::GetAuthTokenRequest request;
  *request.mutable_header() = request_header();
  request.set_token(token_);
  api::GetAuthTokenResponse response;
  grpc::ClientContext context;
  prepare(context, false);
  const auto stub = api::AuthService::NewStub(channels_.channel(kAuthAuthority));
  {
    CallScope scope(*this, context);
    check_status(stub->GetAuthToken(&context, request, &response), "token refresh (GetAuthToken)");
  }
  if (response.status() == api::GetAuthTokenResponse::STATUS_OK && !response.token().empty()) {
    set_token(response.token());
    return;
  }
  login();  // the robot no longer takes the old token: start over with the password
}

void RobotSession::read_robot_id() {
  api::RobotIdRequest request;
  *request.mutable_header() = request_header();
  api::RobotIdResponse response;
  grpc::ClientContext context;
  prepare(context, false);
  const auto stub = api::RobotIdService::NewStub(channels_.channel(kRobotIdAuthority));
  {
    CallScope scope(*this, context);
    check_status(stub->GetRobotId(&context, request, &response), "GetRobotId on id.spot.robot");
  }
  const auto& id = response.robot_id();
  robot_ = (id.nickname().empty() ? id.species() : id.nickname()) + " (serial " + id.serial_number() +
           ", software " + id.version() + ")";
}

void RobotSession::read_directory() {
  api::ListServiceEntriesRequest request;
  *request.mutable_header() = request_header();
  api::ListServiceEntriesResponse response;
  grpc::ClientContext context;
  prepare(context, true);
  const auto stub = api::DirectoryService::NewStub(channels_.channel(kDirectoryAuthority));
  {
    CallScope scope(*this, context);
    check_status(stub->ListServiceEntries(&context, request, &response), "ListServiceEntries on api.spot.robot");
  }
  check_header(response.header(), "ListServiceEntries");
  authorities_.clear();
  for (const auto& entry : response.service_entries()) {
    if (!entry.name().empty() && !entry.authority().empty()) authorities_[entry.name()] = entry.authority();
  }
}

std::shared_ptr<grpc::Channel> RobotSession::service_channel(const std::string& service) const {
  const auto it = authorities_.find(service);
  if (it == authorities_.end()) {
    std::string known;
    for (const auto& [name, _] : authorities_) known += (known.empty() ? "" : ", ") + name;
    throw SpotError(SpotError::Kind::kProtocol, "the robot's directory has no service '" + service + "' (it lists: " +
                                                    (known.empty() ? "nothing" : known) + ")");
  }
  return channels_.channel(it->second);
}

}  // namespace omniview::spot
