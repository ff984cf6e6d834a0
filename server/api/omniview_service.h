// omniview.v1.Omniview over the pipeline: authentication, request checks, limits, and the
// translation of errors into gRPC statuses a person can act on.
#pragma once

#include <map>
#include <mutex>
#include <string>

#include "omniview/v1/omniview.grpc.pb.h"
#include "server/auth/authenticator.h"
#include "server/blackbox/black_box.h"
#include "server/config/daemon_config.h"
#include "server/pipeline/pipeline.h"

namespace omniview {

class OmniviewService final : public v1::Omniview::Service {
 public:
  OmniviewService(Pipeline& pipeline, const Authenticator& auth, const Limits& limits)
      : pipeline_(pipeline), auth_(auth), limits_(limits) {}

  grpc::Status ListCameras(grpc::ServerContext* ctx, const v1::ListCamerasRequest* req,
                           v1::ListCamerasResponse* resp) override;
  grpc::Status CreateView(grpc::ServerContext* ctx, const v1::CreateViewRequest* req, v1::View* resp) override;
  grpc::Status GetView(grpc::ServerContext* ctx, const v1::GetViewRequest* req, v1::View* resp) override;
  grpc::Status ListViews(grpc::ServerContext* ctx, const v1::ListViewsRequest* req,
                         v1::ListViewsResponse* resp) override;
  grpc::Status UpdateView(grpc::ServerContext* ctx, const v1::UpdateViewRequest* req, v1::View* resp) override;
  grpc::Status DeleteView(grpc::ServerContext* ctx, const v1::DeleteViewRequest* req,
                          v1::DeleteViewResponse* resp) override;
  grpc::Status StreamFrames(grpc::ServerContext* ctx, const v1::StreamFramesRequest* req,
                            grpc::ServerWriter<v1::Frame>* writer) override;
  grpc::Status GetSnapshot(grpc::ServerContext* ctx, const v1::SnapshotRequest* req, v1::Frame* resp) override;
  grpc::Status PixelToRay(grpc::ServerContext* ctx, const v1::PixelToRayRequest* req,
                          v1::PixelToRayResponse* resp) override;
  grpc::Status PointToPixel(grpc::ServerContext* ctx, const v1::PointToPixelRequest* req,
                            v1::PointToPixelResponse* resp) override;
  grpc::Status GetStatus(grpc::ServerContext* ctx, const v1::GetStatusRequest* req, v1::Status* resp) override;
  grpc::Status SetJointPositions(grpc::ServerContext* ctx, const v1::SetJointPositionsRequest* req,
                                 v1::JointPositions* resp) override;
  grpc::Status GetJointPositions(grpc::ServerContext* ctx, const v1::GetJointPositionsRequest* req,
                                 v1::JointPositions* resp) override;
  grpc::Status StreamSourceFrames(grpc::ServerContext* ctx, const v1::StreamSourceFramesRequest* req,
                                  grpc::ServerWriter<v1::SourceFrame>* writer) override;
  // Coloured clouds (omniview_service_clouds.cc).
  grpc::Status StreamClouds(grpc::ServerContext* ctx, const v1::StreamCloudsRequest* req,
                            grpc::ServerWriter<v1::PointCloud>* writer) override;
  grpc::Status GetCloud(grpc::ServerContext* ctx, const v1::GetCloudRequest* req, v1::PointCloud* resp) override;
  grpc::Status SaveBlackBox(grpc::ServerContext* ctx, const v1::SaveBlackBoxRequest* req,
                            v1::SaveBlackBoxResponse* resp) override;

  // The daemon's black box, when its config has one (SaveBlackBox refuses without). Before serving.
  void set_black_box(BlackBox* black_box) { black_box_ = black_box; }

 private:
  // Counts a stream against the per-client and total limits for its lifetime.
  class StreamSlot;
  grpc::Status acquire_stream(const std::string& peer);
  void release_stream(const std::string& peer);

  Pipeline& pipeline_;
  BlackBox* black_box_ = nullptr;
  const Authenticator& auth_;
  const Limits limits_;
  std::mutex streams_mutex_;
  std::map<std::string, int> streams_per_peer_;
  int streams_ = 0;
};

// Holds one of the stream limits' places while a stream runs.
class OmniviewService::StreamSlot {
 public:
  StreamSlot(OmniviewService& service, std::string peer) : service_(service), peer_(std::move(peer)) {}
  ~StreamSlot() {
    if (held_) service_.release_stream(peer_);
  }
  grpc::Status acquire() {
    const grpc::Status s = service_.acquire_stream(peer_);
    held_ = s.ok();
    return s;
  }

 private:
  OmniviewService& service_;
  std::string peer_;
  bool held_ = false;
};

}  // namespace omniview
