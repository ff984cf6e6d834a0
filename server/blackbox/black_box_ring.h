// One source's black box on disk: the last minutes of what it delivered, as a ring of short
// recordings ("segments", each an ordinary recording folder, recording.h) in one folder,
// never more than a byte budget, oldest dropped first.
//
//   <folder>/<start>/   a segment: recording.yaml, rig.yaml, frames.csv, images/, clouds/, ...
//                       <start>: its first frame's capture time, ns since the Unix epoch,
//                       zero-padded so names sort by time
//
// Segments rather than one file: dropping the oldest seconds is removing a folder, and a
// write cut short (a crash, a full disk) costs at most the line being written (the
// recording's own guarantee). The ring is read back at start, so it survives a restart.
// Not thread-safe: BlackBox serialises the writer thread and snapshots.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "server/recording/recording.h"
#include "server/source/frame_set.h"

namespace omniview {

struct BlackBoxRingOptions {
  std::chrono::milliseconds span{std::chrono::minutes(5)};  // keep at least this much, no more than a segment over
  uint64_t max_bytes = uint64_t{2} << 30;                   // on disk, in 4 KiB blocks, never more
};

struct RingSegment {
  std::filesystem::path folder;
  uint64_t bytes = 0;  // on disk (files and folders in 4 KiB blocks)
  size_t frame_sets = 0;
  std::chrono::system_clock::time_point first, last;  // capture times
};

class BlackBoxRing {
 public:
  // Reads the segments already in `folder` (creating it), whatever their age (they go when
  // newer frame sets push them out of the span), and drops those that cannot be read
  // (logged through `log`: another version's, or a write cut short before its first frame). Throws std::runtime_error naming the folder when it
  // cannot be created or written.
  BlackBoxRing(std::filesystem::path folder, std::string source, BlackBoxRingOptions options,
               std::function<void(const std::string&)> log = {});
  ~BlackBoxRing();

  // Keeps `frames`: a new segment when the current one is long or big enough, older ones
  // dropped first so the ring stays within max_bytes. Returns false (and keeps nothing)
  // for a frame set bigger than a segment may be; one without any image is passed over.
  // Throws std::runtime_error on a write error (a full disk); the segment is then closed
  // and the oldest one dropped, so the next write starts a fresh one in the room freed.
  bool write(const FrameSet& frames);
  // Closes the segment being written: what is in the ring is complete on disk, and the
  // next write starts a new segment.
  void seal();
  // Hard-links every closed segment's files into `staging` (one folder per segment, in
  // order), at no cost in bytes: a snapshot reads them there while the ring goes on and
  // may drop them. Returns the staged segment folders.
  std::vector<std::filesystem::path> stage(const std::filesystem::path& staging) const;

  const std::filesystem::path& folder() const { return folder_; }
  const std::deque<RingSegment>& segments() const { return segments_; }
  uint64_t bytes() const;
  size_t frame_sets() const;
  // Capture time of the newest frame set minus that of the oldest (0 when empty).
  std::chrono::duration<double> span() const;
  // The longest a segment runs before the next starts: a tenth of the span (2..60 s), so
  // dropping the oldest drops a tenth at a time and the ring keeps its span to that.
  std::chrono::milliseconds segment_length() const;
  // The most bytes one segment holds: an eighth of the budget.
  uint64_t segment_bytes() const { return budget_ / 8; }
  // max_bytes, or less once the disk filled before the ring did (what it held then, less a
  // tenth): the ring then keeps turning in whole segments within the room there is.
  uint64_t budget() const { return budget_; }

 private:
  void start_segment(std::chrono::system_clock::time_point first);
  void drop_oldest();
  void make_room(uint64_t bytes, std::chrono::system_clock::time_point now);

  const std::filesystem::path folder_;
  const std::string source_;
  const BlackBoxRingOptions options_;
  std::function<void(const std::string&)> log_;
  uint64_t budget_ = 0;
  std::deque<RingSegment> segments_;     // oldest first; the back one is being written while writer_ is set
  std::unique_ptr<RecordingWriter> writer_;
};

// Everything under `folder` (files and folders), counted as recording_disk_bytes counts.
uint64_t folder_disk_bytes(const std::filesystem::path& folder);

}  // namespace omniview
