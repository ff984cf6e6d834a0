// One client's stream of one source's coloured clouds: a latest-cloud slot between the
// pipeline and the client's RPC thread, as Subscriber is for frames (subscriber.h). The
// pipeline overwrites the slot and moves on, so a stalled client holds at most one cloud
// here plus what gRPC buffers for it, and never slows the pipeline or another client.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "server/pipeline/errors.h"

#include "omniview/v1/omniview.pb.h"
#include "server/pipeline/cloud/cloud_request.h"

namespace omniview {

using SharedCloud = std::shared_ptr<const v1::PointCloud>;

class CloudSubscriber {
 public:
  CloudSubscriber(std::string peer, CloudRequest request, double max_rate_hz)
      : peer_(std::move(peer)), request_(std::move(request)), max_rate_hz_(max_rate_hz) {}

  const std::string& peer() const { return peer_; }
  const CloudRequest& request() const { return request_; }

  // Pipeline side. True if the subscriber wants a cloud now (open, and its rate allows it).
  bool due(std::chrono::steady_clock::time_point now) const;
  void offer(SharedCloud cloud, std::chrono::steady_clock::time_point now);
  // Ends the stream with this status for the client; later offers are refused.
  void close(ErrorKind code, const std::string& reason);

  // Client side: waits up to `timeout` for a cloud. nullopt on timeout; a null cloud once
  // closed (see close_kind() and close_reason()).
  std::optional<SharedCloud> take(std::chrono::milliseconds timeout);
  ErrorKind close_kind() const;
  std::string close_reason() const;
  void count_sent();

  uint64_t clouds_sent() const;
  uint64_t clouds_dropped() const;

 private:
  const std::string peer_;
  const CloudRequest request_;
  const double max_rate_hz_;

  mutable std::mutex mutex_;
  std::condition_variable ready_;
  SharedCloud slot_;
  bool closed_ = false;
  ErrorKind close_kind_ = ErrorKind::kCancelled;
  std::string close_reason_;
  std::chrono::steady_clock::time_point next_due_{};
  uint64_t sent_ = 0;
  uint64_t dropped_ = 0;
};

}  // namespace omniview
