#include "spot_adapter/mock/services/auth_service.h"

#include "spot_adapter/mock/services/call_gate.h"
#include "spot_adapter/mock/wire/spot_messages.h"

namespace omniview::spot_mock {

using bosdyn::api::GetAuthTokenResponse;

grpc::Status AuthService::GetAuthToken(grpc::ServerContext* ctx, const bosdyn::api::GetAuthTokenRequest* request,
                                       GetAuthTokenResponse* response) {
  if (auto status = admit_call(robot_, *ctx, Token::kNotRequired); !status.ok()) return status;
  const ReturnTrip return_trip(robot_);  // the answer travels back after it is stamped
  const auto received = now_timestamp();
  fill_response_header(request->header(), received, response->mutable_header());

  // A token without a username is a refresh, as the SDKs send it.
  if (request->username().empty() && !request->token().empty()) {
    if (auto fresh = robot_.tokens.refresh(request->token())) {
      robot_.counters.increment(&CounterValues::token_refreshes);
      response->set_status(GetAuthTokenResponse::STATUS_OK);
      response->set_token(*fresh);
    } else {
      response->set_status(GetAuthTokenResponse::STATUS_INVALID_TOKEN);
    }
    return grpc::Status::OK;
  }

  std::string token;
  switch (robot_.tokens.login(request->username(), request->password(), &token)) {
    case LoginResult::kOk:
      robot_.counters.increment(&CounterValues::logins_ok);
      response->set_status(GetAuthTokenResponse::STATUS_OK);
      response->set_token(token);
      break;
    case LoginResult::kInvalidLogin:
      robot_.counters.increment(&CounterValues::logins_failed);
      response->set_status(GetAuthTokenResponse::STATUS_INVALID_LOGIN);
      break;
    case LoginResult::kLockedOut:
      robot_.counters.increment(&CounterValues::logins_failed);
      response->set_status(GetAuthTokenResponse::STATUS_TEMPORARILY_LOCKED_OUT);
      break;
  }
  return grpc::Status::OK;
}

}  // namespace omniview::spot_mock
