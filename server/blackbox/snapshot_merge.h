// A black box snapshot: the ring's segments (each a short recording) joined into one
// ordinary recording, images copied as stored (no decoding), with their joints and clouds.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace omniview {

struct SnapshotSummary {
  std::string source;
  std::filesystem::path folder;
  size_t frame_sets = 0;
  std::chrono::duration<double> span{0};  // newest capture time minus oldest
  uint64_t bytes = 0;                     // on disk
  std::string note;                       // what was left out and why; empty when nothing
};

// Writes `segments` (recording folders, oldest first) as one recording in `out` (which
// must not exist). A segment that cannot be read is left out (said in `note`); where the
// camera set changed, only the segments since the last change are kept (one recording
// keeps one camera set). Throws std::runtime_error naming the file on a write error, or
// when no segment holds a frame.
SnapshotSummary merge_segments(const std::vector<std::filesystem::path>& segments, const std::filesystem::path& out,
                               const std::string& source);

}  // namespace omniview
