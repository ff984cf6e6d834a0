// Bearer tokens: header parsing, roles, the messages a client sees, and that they never
// carry a secret.
#include "server/auth/authenticator.h"

#include <gtest/gtest.h>

namespace omniview {
namespace {

constexpr char kMalformed[] =
    "missing or malformed authorization metadata: send 'authorization: Bearer <token>'";

Authenticator two_roles() {
  return Authenticator({{"viewer-secret", Role::kViewer, "tokens[0] (v)"},
                        {"operator-secret", Role::kOperator, "tokens[1] (o)"}});
}

TEST(BearerToken, Parses) {
  EXPECT_EQ(bearer_token("Bearer abc"), "abc");
  EXPECT_EQ(bearer_token("bearer abc"), "abc");
  EXPECT_EQ(bearer_token("BEARER   abc  "), "abc");
  EXPECT_EQ(bearer_token("Bearer\tabc"), "abc");
  for (const char* bad : {"", "Bearer", "Bearer ", "Bearer    ", "Bearerabc", "Basic abc", "abc",
                          "Bearer a b", "Token abc", " Bearer abc"}) {
    EXPECT_FALSE(bearer_token(bad)) << "'" << bad << "'";
  }
}

TEST(ConstantTimeEquals, ComparesWholeStrings) {
  EXPECT_TRUE(constant_time_equals("", ""));
  EXPECT_TRUE(constant_time_equals("abc", "abc"));
  EXPECT_FALSE(constant_time_equals("abc", "abd"));
  EXPECT_FALSE(constant_time_equals("abc", "ab"));
  EXPECT_FALSE(constant_time_equals("ab", "abc"));
  EXPECT_FALSE(constant_time_equals("abc", std::string_view("abc\0", 4)));
  EXPECT_FALSE(constant_time_equals("", "a"));
}

TEST(Authenticator, Roles) {
  const auto auth = two_roles();
  EXPECT_TRUE(auth.enabled());
  Caller caller;
  EXPECT_TRUE(auth.check_header("Bearer viewer-secret", Role::kViewer, &caller).ok());
  EXPECT_EQ(caller.role, Role::kViewer);
  EXPECT_EQ(caller.label, "tokens[0] (v)");
  EXPECT_TRUE(auth.check_header("Bearer operator-secret", Role::kViewer, &caller).ok());
  EXPECT_EQ(caller.role, Role::kOperator);
  EXPECT_TRUE(auth.check_header("Bearer operator-secret", Role::kOperator).ok());

  const auto denied = auth.check_header("Bearer viewer-secret", Role::kOperator);
  EXPECT_EQ(denied.error_code(), grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_EQ(denied.error_message(), "this call needs the operator role; the token given is a viewer token");
}

TEST(Authenticator, RefusesWithoutAValidToken) {
  const auto auth = two_roles();
  for (const std::optional<std::string_view> header :
       {std::optional<std::string_view>(), std::optional<std::string_view>("viewer-secret"),
        std::optional<std::string_view>("Basic dmlld2VyLXNlY3JldA=="), std::optional<std::string_view>("Bearer ")}) {
    const auto s = auth.check_header(header, Role::kViewer);
    EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(s.error_message(), kMalformed);
  }
  for (const char* wrong : {"Bearer viewer-secre", "Bearer viewer-secret2", "Bearer VIEWER-SECRET", "Bearer x"}) {
    const auto s = auth.check_header(std::string_view(wrong), Role::kViewer);
    EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAUTHENTICATED) << wrong;
    EXPECT_EQ(s.error_message(), "unknown token") << wrong;
  }
  // Two authorization headers are ambiguous, even if one of them is right.
  const auto twice = auth.check_header(std::vector<std::string_view>{"Bearer viewer-secret", "Bearer x"},
                                       Role::kViewer);
  EXPECT_EQ(twice.error_code(), grpc::StatusCode::UNAUTHENTICATED);
}

TEST(Authenticator, MessagesNeverContainASecret) {
  const auto auth = two_roles();
  for (const char* header : {"Bearer viewer-secret", "Bearer operator-secrex", "Bearer viewer-secret "}) {
    for (Role role : {Role::kViewer, Role::kOperator}) {
      const auto s = auth.check_header(std::string_view(header), role);
      EXPECT_EQ(s.error_message().find("secre"), std::string::npos) << s.error_message();
    }
  }
}

TEST(Authenticator, WithoutTokensEveryoneIsAnOperator) {
  const Authenticator auth({});
  EXPECT_FALSE(auth.enabled());
  Caller caller{Role::kViewer, "x"};
  EXPECT_TRUE(auth.check_header(std::nullopt, Role::kOperator, &caller).ok());
  EXPECT_EQ(caller.role, Role::kOperator);
  EXPECT_TRUE(auth.check_header("Bearer anything", Role::kOperator).ok());
}

}  // namespace
}  // namespace omniview
