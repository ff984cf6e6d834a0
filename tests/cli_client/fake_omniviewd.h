// A small in-process stand-in for omniviewd: enough of the API to run the real `omniview`
// client commands against, recording what they asked for. Not the daemon's behaviour in
// detail (the lead's integration tests cover that).
#pragma once

#include <grpcpp/grpcpp.h>

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "omniview/v1/omniview.grpc.pb.h"

namespace omniview::testing {

class FakeOmniviewd final : public v1::Omniview::Service {
 public:
  // `tokens`: token -> "viewer" or "operator"; empty: no authentication. With a PEM
  // certificate and key, it serves TLS.
  explicit FakeOmniviewd(std::map<std::string, std::string> tokens = {}, const std::string& cert_pem = "",
                         const std::string& key_pem = "");
  ~FakeOmniviewd() override;

  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }

  // What the clients sent (copies, under the lock).
  std::vector<v1::CreateViewRequest> creates() const;
  std::vector<v1::UpdateViewRequest> updates() const;
  v1::SnapshotRequest last_snapshot() const;
  v1::StreamFramesRequest last_stream() const;

  grpc::Status ListCameras(grpc::ServerContext*, const v1::ListCamerasRequest*, v1::ListCamerasResponse*) override;
  grpc::Status CreateView(grpc::ServerContext*, const v1::CreateViewRequest*, v1::View*) override;
  grpc::Status GetView(grpc::ServerContext*, const v1::GetViewRequest*, v1::View*) override;
  grpc::Status ListViews(grpc::ServerContext*, const v1::ListViewsRequest*, v1::ListViewsResponse*) override;
  grpc::Status UpdateView(grpc::ServerContext*, const v1::UpdateViewRequest*, v1::View*) override;
  grpc::Status DeleteView(grpc::ServerContext*, const v1::DeleteViewRequest*, v1::DeleteViewResponse*) override;
  grpc::Status StreamFrames(grpc::ServerContext*, const v1::StreamFramesRequest*,
                            grpc::ServerWriter<v1::Frame>*) override;
  grpc::Status GetSnapshot(grpc::ServerContext*, const v1::SnapshotRequest*, v1::Frame*) override;
  grpc::Status GetStatus(grpc::ServerContext*, const v1::GetStatusRequest*, v1::Status*) override;
  grpc::Status StreamSourceFrames(grpc::ServerContext*, const v1::StreamSourceFramesRequest*,
                                  grpc::ServerWriter<v1::SourceFrame>*) override;

  // The frame the fake sends for `sequence`: its data names the encoding and sequence.
  static v1::Frame make_frame(const std::string& view, uint64_t sequence, v1::Encoding encoding);

 private:
  grpc::Status authorize(const grpc::ServerContext* context, bool needs_operator) const;
  grpc::Status find(const std::string& name, v1::View& view) const;

  std::map<std::string, std::string> tokens_;
  mutable std::mutex mutex_;
  std::map<std::string, v1::View> views_;
  std::vector<v1::CreateViewRequest> creates_;
  std::vector<v1::UpdateViewRequest> updates_;
  v1::SnapshotRequest last_snapshot_;
  v1::StreamFramesRequest last_stream_;
  std::unique_ptr<grpc::Server> server_;
  int port_ = 0;
};

}  // namespace omniview::testing
