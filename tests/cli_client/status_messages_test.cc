// Every gRPC status code becomes a message that says what to do.
#include "cli/client/status_messages.h"

#include <gtest/gtest.h>

namespace omniview::cli {
namespace {

using grpc::StatusCode;

const CallContext kCall{"robot:50051", false, true, "--token-file viewer.token", 10};

std::string say(StatusCode code, const std::string& server_message, const CallContext& call = kCall) {
  return describe_status(grpc::Status(code, server_message), call, "view 'front'");
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(StatusMessages, Unavailable) {
  const auto m = say(StatusCode::UNAVAILABLE, "failed to connect to all addresses");
  EXPECT_TRUE(has(m, "cannot reach omniviewd at robot:50051")) << m;
  EXPECT_TRUE(has(m, "is it running?")) << m;
  EXPECT_TRUE(has(m, "--tls-ca")) << m;
  EXPECT_TRUE(has(m, "failed to connect to all addresses")) << m;
}

TEST(StatusMessages, UnavailableFromTheDaemonSaysWhy) {
  const auto down = say(StatusCode::UNAVAILABLE, "omniviewd is shutting down");
  EXPECT_TRUE(has(down, "omniviewd at robot:50051 is shutting down")) << down;
  EXPECT_FALSE(has(down, "cannot reach")) << down;
  const std::string stalled = "no frame of view 'front' within 5000 ms: source 'spot' is not delivering images";
  EXPECT_EQ(say(StatusCode::UNAVAILABLE, stalled), stalled);  // named once, not "view 'front': ... view 'front'"
}

TEST(StatusMessages, MissingClientCertificate) {
  CallContext tls = kCall;
  tls.tls = true;
  const auto m = say(StatusCode::UNAVAILABLE,
                     "failed to connect to all addresses; last error: UNKNOWN: ipv4:127.0.0.1:5: "
                     "error:0A00045C:SSL routines::tlsv13 alert certificate required",
                     tls);
  EXPECT_TRUE(has(m, "requires a client certificate and none was given")) << m;
  EXPECT_TRUE(has(m, "--tls-cert FILE --tls-key FILE")) << m;
  // Any other TLS failure still mentions client certificates among the things to check.
  const auto other = say(StatusCode::UNAVAILABLE, "failed to connect to all addresses", tls);
  EXPECT_TRUE(has(other, "cannot reach")) << other;
  EXPECT_TRUE(has(other, "--tls-cert")) << other;
}

TEST(StatusMessages, UnauthenticatedNamesWhereTokensComeFrom) {
  CallContext no_token = kCall;
  no_token.has_token = false;
  const auto missing = say(StatusCode::UNAUTHENTICATED, "missing token", no_token);
  EXPECT_TRUE(has(missing, "requires a token")) << missing;
  EXPECT_TRUE(has(missing, "--token-file")) << missing;
  EXPECT_TRUE(has(missing, "OMNIVIEW_TOKEN")) << missing;
  const auto rejected = say(StatusCode::UNAUTHENTICATED, "unknown token");
  EXPECT_TRUE(has(rejected, "rejected the token from --token-file viewer.token")) << rejected;
  EXPECT_TRUE(has(rejected, "OMNIVIEW_TOKEN")) << rejected;
}

TEST(StatusMessages, PermissionDeniedAsksForAnOperatorToken) {
  const auto m = say(StatusCode::PERMISSION_DENIED, "this call needs the operator role; the token given is a viewer token");
  EXPECT_TRUE(has(m, "operator token with --token-file")) << m;
  EXPECT_TRUE(has(m, "the token given is a viewer token")) << m;
  EXPECT_EQ(m.find("operator", m.find("operator") + 1), m.find("operator token with"));  // one hint, not two
}

TEST(StatusMessages, NotFoundPassesTheServersMessage) {
  EXPECT_EQ(say(StatusCode::NOT_FOUND, "no view 'frnt' (views: front, rear)"), "no view 'frnt' (views: front, rear)");
  EXPECT_TRUE(has(say(StatusCode::NOT_FOUND, ""), "view 'front': not found"));
}

TEST(StatusMessages, DeadlineNamesTheTimeout) {
  const auto m = say(StatusCode::DEADLINE_EXCEEDED, "");
  EXPECT_TRUE(has(m, "did not answer within 10 s")) << m;
  EXPECT_TRUE(has(m, "--timeout")) << m;
}

TEST(StatusMessages, OtherCodes) {
  EXPECT_TRUE(has(say(StatusCode::INVALID_ARGUMENT, "hfov_deg: must be in (0, 180)"), "view 'front': hfov_deg"));
  EXPECT_TRUE(has(say(StatusCode::ALREADY_EXISTS, ""), "views update"));
  // The daemon's own advice is not repeated in other words.
  EXPECT_EQ(say(StatusCode::ALREADY_EXISTS, "a view named 'front' exists already (update it, or delete it first)"),
            "a view named 'front' exists already (update it, or delete it first)");
  EXPECT_EQ(say(StatusCode::INVALID_ARGUMENT, "view 'front': hfov_deg must be in (0, 180)"),
            "view 'front': hfov_deg must be in (0, 180)");
  EXPECT_TRUE(has(say(StatusCode::RESOURCE_EXHAUSTED, "too many streams"), "too many streams"));
  EXPECT_TRUE(has(say(StatusCode::UNIMPLEMENTED, ""), "older version"));
  EXPECT_TRUE(has(say(StatusCode::INTERNAL, "boom"), "omniviewd failed (boom)"));
  EXPECT_TRUE(has(say(StatusCode::UNKNOWN, ""), "its log"));
  EXPECT_TRUE(has(say(StatusCode::FAILED_PRECONDITION, "source offline"), "source offline"));
  EXPECT_TRUE(has(say(StatusCode::CANCELLED, ""), "cancelled"));
  EXPECT_TRUE(has(say(StatusCode::ABORTED, ""), "try again"));
  // Every code says something.
  for (int code = 1; code <= 16; ++code) {
    EXPECT_FALSE(say(static_cast<StatusCode>(code), "").empty()) << code;
  }
}

}  // namespace
}  // namespace omniview::cli
