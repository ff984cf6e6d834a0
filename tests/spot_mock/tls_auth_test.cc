// TLS per authority, login, lockout, refresh and the token every other service requires.
#include <thread>

#include "bosdyn/api/auth_service.grpc.pb.h"
#include "bosdyn/api/directory_service.grpc.pb.h"
#include "bosdyn/api/image_service.grpc.pb.h"
#include "bosdyn/api/robot_id_service.grpc.pb.h"
#include "spot_adapter/mock/auth/token_store.h"
#include "tests/spot_mock/mock_fixture.h"

namespace omniview::testing {
namespace {

using bosdyn::api::GetAuthTokenResponse;

class SpotMockAuth : public SharedMockTest {
 protected:
  GetAuthTokenResponse get_token(const std::string& user, const std::string& password, const std::string& token = "") {
    auto stub = bosdyn::api::AuthService::NewStub(mock().channel("auth.spot.robot"));
    bosdyn::api::GetAuthTokenRequest request;
    request.mutable_header()->set_client_name("auth-test");
    request.set_username(user);
    request.set_password(password);
    request.set_token(token);
    GetAuthTokenResponse response;
    const grpc::Status status = stub->GetAuthToken(spot_context().get(), request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response;
  }
  grpc::Status list_images(const std::unique_ptr<grpc::ClientContext>& ctx) {
    auto stub = bosdyn::api::ImageService::NewStub(mock().channel("api.spot.robot"));
    bosdyn::api::ListImageSourcesResponse response;
    return stub->ListImageSources(ctx.get(), {}, &response);
  }
};

TEST_F(SpotMockAuth, EachAuthorityAnswersWithItsOwnCertificate) {
  // The channel checks the certificate against the authority: a call only succeeds if the
  // mock picked that authority's certificate by SNI.
  bosdyn::api::RobotIdResponse id;
  EXPECT_TRUE(bosdyn::api::RobotIdService::NewStub(mock().channel("id.spot.robot"))
                  ->GetRobotId(spot_context().get(), {}, &id)
                  .ok());
  EXPECT_EQ(id.robot_id().species(), "spot");
  const std::string token = mock().login();  // on auth.spot.robot
  EXPECT_FALSE(token.empty());
  bosdyn::api::ListServiceEntriesResponse entries;
  const grpc::Status api = bosdyn::api::DirectoryService::NewStub(mock().channel("api.spot.robot"))
                               ->ListServiceEntries(spot_context(token).get(), {}, &entries);
  EXPECT_TRUE(api.ok()) << api.error_message();

  bosdyn::api::RobotIdResponse ignored;
  const grpc::Status wrong = bosdyn::api::RobotIdService::NewStub(mock().channel("robot.example.com"))
                                 ->GetRobotId(spot_context("", std::chrono::seconds(3)).get(), {}, &ignored);
  EXPECT_EQ(wrong.error_code(), grpc::StatusCode::UNAVAILABLE) << "no certificate names robot.example.com";
}

TEST_F(SpotMockAuth, LoginGivesAJwtShapedTokenWithTheConfiguredLifetime) {
  const auto response = get_token(mock().username(), mock().password());
  EXPECT_EQ(response.status(), GetAuthTokenResponse::STATUS_OK);
  EXPECT_EQ(response.header().error().code(), bosdyn::api::CommonError::CODE_OK);
  EXPECT_EQ(response.header().request_header().client_name(), "auth-test");
  EXPECT_TRUE(response.header().has_response_timestamp());
  const auto claims = spot_mock::decode_token_claims(response.token());
  ASSERT_TRUE(claims) << "not header.payload.signature with exp/iat/sub";
  EXPECT_EQ(claims->exp - claims->iat, kSharedTokenLifetimeS);
  EXPECT_EQ(claims->sub, mock().username());
  EXPECT_NEAR(double(claims->iat), double(std::time(nullptr)), 60);
}

TEST_F(SpotMockAuth, WrongPasswordThenLockoutEvenForTheRightOne) {
  counters(true);
  EXPECT_EQ(get_token(mock().username(), "wrong").status(), GetAuthTokenResponse::STATUS_INVALID_LOGIN);
  EXPECT_EQ(get_token("nobody", mock().password()).status(), GetAuthTokenResponse::STATUS_INVALID_LOGIN);
  EXPECT_EQ(get_token(mock().username(), mock().password()).status(), GetAuthTokenResponse::STATUS_OK)
      << "a good login resets the count";
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(get_token(mock().username(), "wrong").status(), GetAuthTokenResponse::STATUS_INVALID_LOGIN) << i;
  }
  const auto locked = get_token(mock().username(), mock().password());
  EXPECT_EQ(locked.status(), GetAuthTokenResponse::STATUS_TEMPORARILY_LOCKED_OUT);
  EXPECT_TRUE(locked.token().empty());
  std::this_thread::sleep_for(std::chrono::milliseconds(kSharedLockoutS * 1000 + 200));
  EXPECT_EQ(get_token(mock().username(), mock().password()).status(), GetAuthTokenResponse::STATUS_OK);
  const auto c = counters();
  EXPECT_EQ(c.logins_ok(), 2u);
  EXPECT_EQ(c.logins_failed(), 9u);
}

TEST_F(SpotMockAuth, RefreshNeedsAValidTokenAndGivesANewOne) {
  const std::string token = mock().login();
  counters(true);
  const auto refreshed = get_token("", "", token);
  EXPECT_EQ(refreshed.status(), GetAuthTokenResponse::STATUS_OK);
  EXPECT_NE(refreshed.token(), token);
  EXPECT_TRUE(list_images(spot_context(refreshed.token())).ok());
  EXPECT_EQ(get_token("", "", "not.a.token").status(), GetAuthTokenResponse::STATUS_INVALID_TOKEN);
  EXPECT_EQ(counters().token_refreshes(), 1u);
}

TEST_F(SpotMockAuth, ServicesOtherThanAuthAndIdNeedABearerToken) {
  counters(true);
  const grpc::Status none = list_images(spot_context());
  EXPECT_EQ(none.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_NE(none.error_message().find("authorization: Bearer"), std::string::npos) << none.error_message();
  EXPECT_EQ(list_images(spot_context("forged.token.value")).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  auto no_scheme = spot_context();
  no_scheme->AddMetadata("authorization", mock().login());
  EXPECT_EQ(list_images(no_scheme).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(counters().auth_rejections(), 3u);
  EXPECT_TRUE(list_images(spot_context(mock().login())).ok());
}

TEST_F(SpotMockAuth, ExpiringTokensRevokesEveryTokenIssuedSoFar) {
  const std::string token = mock().login();
  ASSERT_TRUE(list_images(spot_context(token)).ok());
  const auto out = mock().control("--expire-tokens");
  EXPECT_EQ(out.exit_code, 0) << out.text;
  EXPECT_EQ(list_images(spot_context(token)).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(get_token("", "", token).status(), GetAuthTokenResponse::STATUS_INVALID_TOKEN);
  EXPECT_TRUE(list_images(spot_context(mock().login())).ok()) << "a new login works";
}

}  // namespace
}  // namespace omniview::testing
