// The one seam every front end goes through (server/status/failure.h, server/pipeline/
// subscription.h): each error kind says one thing on every port, and a subscription leaves
// the pipeline exactly once however it ends.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

#include "server/api/status_message.h"
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

// GetStatus's message is the pipeline's report and the black box's rings, field for field;
// a fixed view leaves the depth fields at zero, as before the report had its own types.
TEST(StatusMessage, CarriesEveryReportFieldAndLeavesFixedViewsDepthAtZero) {
  PipelineReport report;
  report.uptime_s = 12.5;
  SourceReport source;
  source.name = "spot";
  source.type = "spot";
  source.connected = true;
  source.rate_hz = 15;
  source.last_frame_age_s = 0.05;
  source.frames = 100;
  source.errors = 2;
  source.dropped = 3;
  source.message = "slow";
  source.active_cameras = {"frontleft", "frontright"};
  source.failure_rate = 0.2;
  source.degraded = true;
  report.sources.push_back(source);
  ViewReport fixed;
  fixed.name = "front";
  fixed.subscribers = 2;
  fixed.fps = 14.9;
  fixed.map_pending = true;
  report.views.push_back(fixed);
  ViewReport measured;
  measured.name = "birdseye";
  measured.depth = DepthReport{1.5, 3.25, 7, 0.8, "waiting"};
  report.views.push_back(measured);
  report.clients.push_back({"ipv4:127.0.0.1:5000", "front", 10, 1, "h264 q80"});
  BlackBoxRingReport ring;
  ring.source = "spot";
  ring.bytes = 4096;
  ring.last_snapshot = "snap";

  const v1::Status status = status_message(report, {ring});
  EXPECT_EQ(status.version(), OMNIVIEW_VERSION);
  EXPECT_EQ(status.uptime_s(), 12.5);
  ASSERT_EQ(status.sources_size(), 1);
  const auto& s = status.sources(0);
  EXPECT_EQ(s.name(), "spot");
  EXPECT_TRUE(s.connected());
  EXPECT_EQ(s.rate_hz(), 15);
  EXPECT_EQ(s.last_frame_age_s(), 0.05);
  EXPECT_EQ(s.frames(), 100u);
  EXPECT_EQ(s.errors(), 2u);
  EXPECT_EQ(s.dropped(), 3u);
  EXPECT_EQ(s.message(), "slow");
  ASSERT_EQ(s.active_cameras_size(), 2);
  EXPECT_EQ(s.active_cameras(1), "frontright");
  EXPECT_EQ(s.failure_rate(), 0.2);
  EXPECT_TRUE(s.degraded());
  ASSERT_EQ(status.views_size(), 2);
  EXPECT_EQ(status.views(0).subscribers(), 2u);
  EXPECT_TRUE(status.views(0).map_pending());
  EXPECT_EQ(status.views(0).depth_geometry_age_s(), 0);  // fixed: zero, not -1
  EXPECT_EQ(status.views(0).depth_message(), "");
  EXPECT_EQ(status.views(1).depth_geometry_age_s(), 1.5);
  EXPECT_EQ(status.views(1).depth_update_ms(), 3.25);
  EXPECT_EQ(status.views(1).depth_updates(), 7u);
  EXPECT_EQ(status.views(1).measured_depth(), 0.8);
  EXPECT_EQ(status.views(1).depth_message(), "waiting");
  ASSERT_EQ(status.clients_size(), 1);
  EXPECT_EQ(status.clients(0).encoding(), "h264 q80");
  EXPECT_EQ(status.clients(0).frames_dropped(), 1u);
  ASSERT_EQ(status.blackbox_size(), 1);
  EXPECT_EQ(status.blackbox(0).bytes(), 4096u);
  EXPECT_EQ(status.blackbox(0).last_snapshot(), "snap");
}

}  // namespace
}  // namespace omniview
