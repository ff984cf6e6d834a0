// Splits an MJPEG file (JPEG images back to back, as `ffmpeg -c:v copy out.mjpeg` or a
// UVC capture writes them) into frames, and reads the timestamps beside a recording.
// Both read outside data: tests/fuzz/mjpeg_frames_fuzz.cc feeds them anything.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace omniview::insta360 {

// [offset, size) of each JPEG in `data`: from a start-of-image marker (FF D8 FF) to the
// end-of-image marker (FF D9) that ends its entropy-coded data. Garbage between frames
// is skipped; a last frame without its end is dropped.
std::vector<std::pair<size_t, size_t>> split_mjpeg(const uint8_t* data, size_t size);

// Why these bytes cannot be a whole JPEG frame (empty: they may be): no start marker, no
// end marker (truncated), larger than `max_size`.
std::string mjpeg_frame_problem(const uint8_t* data, size_t size, size_t max_size = size_t{64} << 20);

// A timestamps file: one capture time in seconds per line (any offset; '#' comments and
// blank lines are ignored), optionally followed by a file name ("0.033 frame_0001.jpg").
// Times must increase. Throws std::runtime_error naming `what` and the line.
struct TimedEntry {
  double seconds = 0;
  std::string file;  // empty when the line names none
};
std::vector<TimedEntry> parse_timestamps(const std::string& text, const std::string& what);

}  // namespace omniview::insta360
