#include "server/pipeline/subscriber.h"

#include <algorithm>

#include "server/pipeline/video_stream.h"

namespace omniview {

Subscriber::Subscriber(std::string peer, EncodingKey key, std::shared_ptr<VideoStream> video, bool stale_frames)
    : peer_(std::move(peer)), key_(key), max_rate_hz_(0), stale_frames_(stale_frames), video_(std::move(video)) {
  video_->request_key_frame();  // a joining client starts at once, not at the next periodic key frame
}

Subscriber::~Subscriber() = default;

bool Subscriber::due(std::chrono::steady_clock::time_point now) const {
  std::lock_guard lock(mutex_);
  return !closed_ && now >= next_due_;
}

void Subscriber::offer(SharedFrame frame, std::chrono::steady_clock::time_point now) {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    if (frame->camera().revision() < min_revision_) {
      // Rendered before the view changed (an encode in flight across the update).
      if (video_) {
        lose_video_frame();
      } else {
        ++dropped_;
      }
      return;
    }
    if (video_ && !offer_video(frame)) return;
    if (slot_) ++dropped_;  // the client has not taken the previous one: it is stale now
    slot_ = std::move(frame);
    if (max_rate_hz_ > 0) {
      // Schedule from the nominal time, not `now`, so jitter does not lower the rate; but
      // never let a backlog of "due" slots build up after a pause.
      const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(1.0 / max_rate_hz_));
      next_due_ = std::max(next_due_ + period, now + period / 2);
    }
  }
  ready_.notify_one();
}

// Under the lock. A frame that depends on one the client did not get is refused, and so is
// the one in the slot when it is replaced: from there on only a key frame is taken.
bool Subscriber::offer_video(const SharedFrame& frame) {
  if (frame->key_frame()) {
    awaiting_key_ = false;
    started_ = true;
    return true;
  }
  if (!awaiting_key_ && !slot_) return true;  // the next frame after the one the client took
  if (started_) {
    dropped_ += slot_ ? 2 : 1;
  }
  slot_.reset();
  awaiting_key_ = true;
  return false;
}

// Under the lock. A video client misses an encoded frame of an old revision (counted here,
// with the one in the slot, if any, which refers to it). The frames coded after it refer
// to it, so the client waits for a key frame, and the encoder makes the first frame of the
// current revision one, whatever its key frame interval: the stream goes on with the next
// picture of the new view.
void Subscriber::lose_video_frame() {
  if (started_) dropped_ += slot_ ? 2 : 1;
  slot_.reset();
  awaiting_key_ = true;
  video_->request_key_frame_at(min_revision_);
}

void Subscriber::set_min_revision(uint64_t revision) {
  std::lock_guard lock(mutex_);
  min_revision_ = std::max(min_revision_, revision);
  if (!slot_ || slot_->camera().revision() >= min_revision_) return;
  if (video_) {
    slot_.reset();  // the frame lost: lose_video_frame counts it
    lose_video_frame();
    return;
  }
  ++dropped_;
  slot_.reset();
}

void Subscriber::count_dropped() {
  std::lock_guard lock(mutex_);
  ++dropped_;
}

void Subscriber::close(ErrorKind code, const std::string& reason) {
  {
    std::lock_guard lock(mutex_);
    if (closed_) return;
    closed_ = true;
    close_kind_ = code;
    close_reason_ = reason;
  }
  ready_.notify_all();
}

std::optional<SharedFrame> Subscriber::take(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  // A video client that lost frames asks for a key frame only now that it reads again: a
  // stalled client does not make the shared encoder send key frames to everybody. So does
  // one that joined and has none yet: the key frame its arrival asked for may have gone to
  // a frame rendered just before it joined, to the others only.
  if (video_ && awaiting_key_ && !slot_ && !closed_) video_->request_key_frame();
  ready_.wait_for(lock, timeout, [&] { return slot_ || closed_; });
  if (slot_) return std::exchange(slot_, nullptr);
  if (closed_) return SharedFrame{};
  return std::nullopt;
}

ErrorKind Subscriber::close_kind() const {
  std::lock_guard lock(mutex_);
  return close_kind_;
}

std::string Subscriber::close_reason() const {
  std::lock_guard lock(mutex_);
  return close_reason_;
}

bool Subscriber::hand_over(const v1::Frame& frame) {
  std::lock_guard lock(mutex_);
  if (frame.camera().revision() < min_revision_) {
    if (video_) {
      lose_video_frame();  // and the frame after it in the slot, which refers to it
    } else {
      ++dropped_;
    }
    return false;
  }
  ++sent_;
  // A player that probes the start of a stream and drops what it probed (ffplay -fflags
  // nobuffer) used up the stream's first key frame: a second comes a quarter second later
  // (the group's kMinKeyInterval) rather than with the periodic one 10 s later (issue 29).
  if (video_ && frame.key_frame() && ++key_frames_sent_ == 1) video_->request_key_frame();
  return true;
}

uint64_t Subscriber::frames_sent() const {
  std::lock_guard lock(mutex_);
  return sent_;
}

void Subscriber::starts_reading() {
  std::lock_guard lock(mutex_);
  dropped_ = 0;
}

uint64_t Subscriber::frames_dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace omniview
