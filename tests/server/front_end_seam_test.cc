// The one seam every front end goes through (server/status/failure.h, server/pipeline/
// subscription.h): each error kind says one thing on every port, and a subscription leaves
// the pipeline exactly once however it ends.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

#include "server/pipeline/subscription.h"
#include "server/status/failure.h"

namespace omniview {
namespace {

const ErrorKind kAll[] = {ErrorKind::kCancelled,        ErrorKind::kInvalidArgument,  ErrorKind::kDeadlineExceeded,
                          ErrorKind::kNotFound,         ErrorKind::kAlreadyExists,    ErrorKind::kPermissionDenied,
                          ErrorKind::kResourceExhausted, ErrorKind::kFailedPrecondition, ErrorKind::kAborted,
                          ErrorKind::kOutOfRange,       ErrorKind::kUnimplemented,    ErrorKind::kInternal,
                          ErrorKind::kUnavailable,      ErrorKind::kUnauthenticated};

TEST(FailureMapping, EachKindHasItsOwnGrpcCodeAndNameAndComesBackFromIt) {
  std::set<grpc::StatusCode> codes;
  std::set<std::string_view> names;
  for (const ErrorKind kind : kAll) {
    const grpc::StatusCode code = grpc_code(kind);
    EXPECT_NE(code, grpc::StatusCode::OK);
    EXPECT_TRUE(codes.insert(code).second) << status_name(kind) << ": a gRPC code two kinds share";
    EXPECT_TRUE(names.insert(status_name(kind)).second);
    EXPECT_EQ(kind_of(code), kind) << status_name(kind);
    const int http = http_status(kind);
    EXPECT_TRUE(http >= 400 && http < 600) << status_name(kind) << ": " << http;
  }
  // The names the WebSocket protocols send are gRPC's own.
  EXPECT_EQ(status_name(ErrorKind::kNotFound), "NOT_FOUND");
  EXPECT_EQ(status_name(ErrorKind::kResourceExhausted), "RESOURCE_EXHAUSTED");
  EXPECT_EQ(http_status(ErrorKind::kNotFound), 404);
  EXPECT_EQ(http_status(ErrorKind::kUnauthenticated), 401);
  EXPECT_EQ(http_status(ErrorKind::kPermissionDenied), 403);
  EXPECT_EQ(http_status(ErrorKind::kUnavailable), 503);
  EXPECT_EQ(kind_of(grpc::StatusCode::DATA_LOSS), ErrorKind::kInternal);  // nothing here says it
}

Failure failure_of(const std::function<void()>& thrower) {
  try {
    thrower();
  } catch (...) {
    return current_failure();
  }
  ADD_FAILURE() << "nothing was thrown";
  return {};
}

TEST(FailureMapping, AnyExceptionBecomesOneFailure) {
  Failure f = failure_of([] { throw PipelineError(ErrorKind::kNotFound, "no view 'x'"); });
  EXPECT_EQ(f.kind, ErrorKind::kNotFound);
  EXPECT_EQ(f.message, "no view 'x'");
  f = failure_of([] { throw std::invalid_argument("width: must be > 0"); });
  EXPECT_EQ(f.kind, ErrorKind::kInvalidArgument);
  EXPECT_EQ(f.message, "width: must be > 0");
  f = failure_of([] { throw std::runtime_error("disk full"); });
  EXPECT_EQ(f.kind, ErrorKind::kInternal);
  EXPECT_EQ(f.message, "internal error: disk full");
  f = failure_of([] { throw 42; });
  EXPECT_EQ(f.kind, ErrorKind::kInternal);
  EXPECT_EQ(f.message, "internal error");
}

TEST(FailureMapping, AGrpcStatusMessageStaysFarBelowTheMetadataLimit) {
  const grpc::Status s = grpc_status(grpc::StatusCode::INVALID_ARGUMENT, std::string(100000, 'x'));
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_LT(s.error_message().size(), 4096u);
}

struct Item {};

TEST(Subscription, LeavesOnceHoweverItEnds) {
  int left = 0;
  const auto leave = [&](const Item*) { ++left; };
  {
    Subscription<Item> s(std::make_shared<Item>(), leave);
    EXPECT_TRUE(s);
  }
  EXPECT_EQ(left, 1);  // end of scope
  {
    Subscription<Item> a(std::make_shared<Item>(), leave);
    Subscription<Item> b = std::move(a);
    EXPECT_FALSE(a);  // NOLINT(bugprone-use-after-move): moved-from is empty by contract
    Subscription<Item> c;
    c = std::move(b);
    c.reset();
    c.reset();
  }
  EXPECT_EQ(left, 2);  // moved twice, reset twice: left once
  {
    Subscription<Item> a(std::make_shared<Item>(), leave);
    a = Subscription<Item>(std::make_shared<Item>(), leave);  // the old one leaves as it is replaced
    EXPECT_EQ(left, 3);
  }
  EXPECT_EQ(left, 4);
  // A leave that throws (the pipeline stopping meanwhile) ends nothing else.
  { Subscription<Item> s(std::make_shared<Item>(), [](const Item*) { throw std::runtime_error("stopped"); }); }
}

}  // namespace
}  // namespace omniview
