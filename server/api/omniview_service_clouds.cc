// StreamClouds and GetCloud: a source's coloured lidar clouds (docs/API.md, "Point clouds").
#include <sstream>

#include "server/api/omniview_service.h"
#include "server/api/service_support.h"

namespace omniview {

namespace {

using service_support::guarded;
using service_support::closed_status;

}  // namespace

grpc::Status OmniviewService::StreamClouds(grpc::ServerContext* ctx, const v1::StreamCloudsRequest* req,
                                           grpc::ServerWriter<v1::PointCloud>* writer) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    CloudRequest request = cloud_request_from_proto(req->options());
    const double rate = req->max_rate_hz() == 0 ? limits_.max_rate_hz : std::min(req->max_rate_hz(), limits_.max_rate_hz);
    std::ostringstream served;
    served << rate;
    ctx->AddInitialMetadata("omniview-max-rate-hz", served.str());
    ctx->AddInitialMetadata("omniview-stream-limits",
                            "delivery=latest-cloud-wins; max_rate_hz=" + served.str() +
                                "; max_streams_per_connection=" + std::to_string(limits_.max_streams_per_client) +
                                "; max_streams=" + std::to_string(limits_.max_streams) +
                                "; max_message_bytes=" + std::to_string(limits_.max_message_bytes));
    StreamSlot slot(*this, ctx->peer());
    if (auto s = slot.acquire(); !s.ok()) return s;
    const auto subscriber = pipeline_.subscribe_cloud(req->source(), ctx->peer(), std::move(request), rate);
    while (true) {
      if (ctx->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "client cancelled");
      const auto cloud = subscriber->take(kFrontEndPoll);
      if (!cloud) continue;  // timed out: check for cancellation and wait again
      if (!*cloud) return closed_status(*subscriber);
      if (!writer->Write(**cloud)) return grpc::Status(grpc::StatusCode::CANCELLED, "client went away");
      subscriber->count_sent();
    }
  });
}

grpc::Status OmniviewService::GetCloud(grpc::ServerContext* ctx, const v1::GetCloudRequest* req,
                                       v1::PointCloud* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    const int timeout_ms = req->timeout_ms() > 0 ? req->timeout_ms() : 5000;
    const auto subscriber =
        pipeline_.subscribe_cloud(req->source(), ctx->peer(), cloud_request_from_proto(req->options()), 0);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (std::chrono::steady_clock::now() < deadline) {
      if (ctx->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "client cancelled");
      const auto cloud = subscriber->take(kFrontEndPoll);
      if (!cloud) continue;
      if (!*cloud) return closed_status(*subscriber);
      *resp = **cloud;
      return grpc::Status::OK;
    }
    const std::string source = req->source().empty() ? "the first source" : "source '" + req->source() + "'";
    return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                        "no cloud within " + std::to_string(timeout_ms) + " ms: " + source +
                            " is not delivering clouds with images (see `omniview status`)");
  });
}

}  // namespace omniview
