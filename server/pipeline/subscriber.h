// One client's stream of one view: a latest-frame slot between the pipeline and the
// client's RPC thread.
//
// The pipeline never waits on a client: it overwrites the slot (counting the frame it
// replaces as dropped) and moves on. A stalled client therefore holds at most the frame in
// its slot plus what gRPC has buffered for it, whatever it does. Closed (the stream ended,
// or the client left), it refuses every later offer, so encodes still in flight cannot
// reach it.
//
// A view update raises the subscriber's revision floor (set_min_revision) before UpdateView
// returns; a frame of an older revision is then refused wherever it is: offered, in the
// slot, or taken by the client's thread and not yet handed to the transport (hand_over).
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

namespace omniview {

// What a client asked for; frames are encoded once per distinct key.
struct EncodingKey {
  v1::Encoding encoding = v1::JPEG;
  int quality = 85;
  bool gray = false;
  // H264 only (0 for the still encodings, so that they never split their groups): the
  // bitrate ceiling, and the rate (millihertz) the group's one encoder runs at: clients of
  // a video stream share every frame, so they must share the rate too.
  int max_kbps = 0;
  int rate_mhz = 0;
  auto operator<=>(const EncodingKey&) const = default;
};

using SharedFrame = std::shared_ptr<const v1::Frame>;

class VideoStream;

class Subscriber {
 public:
  Subscriber(std::string peer, EncodingKey key, double max_rate_hz, bool stale_frames = false)
      : peer_(std::move(peer)), key_(key), max_rate_hz_(max_rate_hz), stale_frames_(stale_frames) {}
  // A video client (H264): `video` is its group's shared encoder, which paces the frames
  // (this subscriber's own rate is then 0). Its slot keeps the stream decodable: a client
  // that missed a frame gets nothing until the next key frame, asked of `video` as soon
  // as the client is ready to read again; it starts at a key frame too.
  Subscriber(std::string peer, EncodingKey key, std::shared_ptr<VideoStream> video, bool stale_frames);
  ~Subscriber();

  // The group's shared encoder (H264), or null.
  const std::shared_ptr<VideoStream>& video() const { return video_; }

  const std::string& peer() const { return peer_; }
  const EncodingKey& key() const { return key_; }
  // The client asked for the last picture again, marked stale, while the source is silent.
  bool stale_frames() const { return stale_frames_; }

  // Pipeline side. True if the subscriber wants a frame now (its rate allows it).
  bool due(std::chrono::steady_clock::time_point now) const;
  void offer(SharedFrame frame, std::chrono::steady_clock::time_point now);
  // After a view update: frames rendered before revision `revision` are stale; drop any in
  // the slot and refuse later offers and hand-overs of them, so the next frame the client
  // gets reflects the change. A video client that loses an encoded frame this way resumes
  // at the first key frame of the new revision, asked of the group's encoder at once.
  void set_min_revision(uint64_t revision);
  // A frame meant for this subscriber was replaced by a newer one before it was encoded, or
  // not encoded because the view changed meanwhile.
  void count_dropped();

  // Ends the stream with this status for the client.
  void close(ErrorKind code, const std::string& reason);

  // Client side: waits up to `timeout` for a frame. nullopt on timeout; a null frame once
  // closed (see close_kind() and close_reason()).
  std::optional<SharedFrame> take(std::chrono::milliseconds timeout);
  ErrorKind close_kind() const;
  std::string close_reason() const;
  // The last check, right before a taken frame goes to the transport: false when the view
  // changed since the frame was rendered (it is dropped, and counted so); true counts it as
  // sent. Ordered with set_min_revision by the lock, so no frame passes it once the update
  // that raised the floor has returned.
  bool hand_over(const v1::Frame& frame);

  uint64_t frames_sent() const;
  uint64_t frames_dropped() const;
  // The client starts reading only now (a WebRTC viewer, after its offer was answered):
  // frames replaced in the slot before then were not lost by reading too slowly, and are
  // not counted as dropped.
  void starts_reading();

 private:
  bool offer_video(const SharedFrame& frame);
  void lose_video_frame();

  uint64_t key_frames_sent_ = 0;  // under mutex_
  const std::string peer_;
  const EncodingKey key_;
  const double max_rate_hz_;
  const bool stale_frames_;
  const std::shared_ptr<VideoStream> video_;

  mutable std::mutex mutex_;
  std::condition_variable ready_;
  SharedFrame slot_;
  bool closed_ = false;
  ErrorKind close_kind_ = ErrorKind::kCancelled;
  std::string close_reason_;
  std::chrono::steady_clock::time_point next_due_{};
  uint64_t min_revision_ = 0;  // frames of older revisions are refused
  bool awaiting_key_ = true;  // video: the next frame this client can decode is a key frame
  bool started_ = false;      // video: a key frame reached the slot (drops count from then)
  uint64_t sent_ = 0;  // handed to the transport
  uint64_t dropped_ = 0;
};

}  // namespace omniview
