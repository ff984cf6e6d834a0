// One client's stream of one view: a latest-frame slot between the pipeline and the
// client's RPC thread.
//
// The pipeline never waits on a client: it overwrites the slot (counting the frame it
// replaces as dropped) and moves on. A stalled client therefore holds at most the frame in
// its slot plus what gRPC has buffered for it, whatever it does. Closed (the stream ended,
// or the client left), it refuses every later offer, so encodes still in flight cannot
// reach it.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <grpcpp/support/status_code_enum.h>

#include "omniview/v1/omniview.pb.h"

namespace omniview {

// What a client asked for; frames are encoded once per distinct key.
struct EncodingKey {
  v1::Encoding encoding = v1::JPEG;
  int quality = 85;
  bool gray = false;
  auto operator<=>(const EncodingKey&) const = default;
};

using SharedFrame = std::shared_ptr<const v1::Frame>;

class Subscriber {
 public:
  Subscriber(std::string peer, EncodingKey key, double max_rate_hz, bool stale_frames = false)
      : peer_(std::move(peer)), key_(key), max_rate_hz_(max_rate_hz), stale_frames_(stale_frames) {}

  const std::string& peer() const { return peer_; }
  const EncodingKey& key() const { return key_; }
  // The client asked for the last picture again, marked stale, while the source is silent.
  bool stale_frames() const { return stale_frames_; }

  // Pipeline side. True if the subscriber wants a frame now (its rate allows it).
  bool due(std::chrono::steady_clock::time_point now) const;
  void offer(SharedFrame frame, std::chrono::steady_clock::time_point now);
  // After a view update: frames rendered before revision `revision` are stale; drop any in
  // the slot and refuse later offers of them, so the next frame taken reflects the change.
  void set_min_revision(uint64_t revision);
  // A frame meant for this subscriber was replaced by a newer one before it was encoded.
  void count_dropped();

  // Ends the stream with this status for the client.
  void close(grpc::StatusCode code, const std::string& reason);

  // Client side: waits up to `timeout` for a frame. nullopt on timeout; a null frame once
  // closed (see close_code() and close_reason()).
  std::optional<SharedFrame> take(std::chrono::milliseconds timeout);
  grpc::StatusCode close_code() const;
  std::string close_reason() const;
  void count_sent();

  uint64_t frames_sent() const;
  uint64_t frames_dropped() const;

 private:
  const std::string peer_;
  const EncodingKey key_;
  const double max_rate_hz_;
  const bool stale_frames_;

  mutable std::mutex mutex_;
  std::condition_variable ready_;
  SharedFrame slot_;
  bool closed_ = false;
  grpc::StatusCode close_code_ = grpc::StatusCode::OK;
  std::string close_reason_;
  std::chrono::steady_clock::time_point next_due_{};
  uint64_t min_revision_ = 0;
  uint64_t sent_ = 0;
  uint64_t dropped_ = 0;
};

}  // namespace omniview
