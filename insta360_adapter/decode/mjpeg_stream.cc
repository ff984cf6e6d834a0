#include "insta360_adapter/decode/mjpeg_stream.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace omniview::insta360 {

std::vector<std::pair<size_t, size_t>> split_mjpeg(const uint8_t* data, size_t size) {
  std::vector<std::pair<size_t, size_t>> frames;
  size_t i = 0;
  while (i + 3 <= size) {
    if (!(data[i] == 0xFF && data[i + 1] == 0xD8 && data[i + 2] == 0xFF)) {
      ++i;
      continue;
    }
    const size_t start = i;
    size_t j = i + 2;
    bool ended = false;
    // Walk the marker segments up to start-of-scan, then scan the entropy-coded data for
    // FF D9 (inside it, FF is always followed by 00 or a restart marker D0-D7).
    while (j + 4 <= size) {
      if (data[j] != 0xFF) break;  // not a marker where one must be: corrupt header
      const uint8_t marker = data[j + 1];
      if (marker == 0xFF) {  // fill byte
        ++j;
        continue;
      }
      if (marker == 0xD9) {
        ended = true;
        j += 2;
        break;
      }
      const size_t length = size_t{data[j + 2]} << 8 | data[j + 3];
      if (length < 2) break;
      j += 2 + length;
      if (marker == 0xDA) {  // start of scan: entropy-coded data follows
        while (j + 1 < size) {
          if (data[j] == 0xFF && data[j + 1] != 0x00 && !(data[j + 1] >= 0xD0 && data[j + 1] <= 0xD7)) break;
          ++j;
        }
      }
    }
    if (ended && j <= size) {
      frames.emplace_back(start, j - start);
      i = j;
    } else {
      i = start + 2;  // look for the next frame
    }
  }
  return frames;
}

std::string mjpeg_frame_problem(const uint8_t* data, size_t size, size_t max_size) {
  if (size > max_size) return "frame of " + std::to_string(size) + " bytes is larger than " + std::to_string(max_size);
  if (size < 4 || data[0] != 0xFF || data[1] != 0xD8) return "no JPEG start-of-image marker";
  // UVC cameras may pad a frame after its end marker: look at the last few bytes.
  for (size_t k = size; k >= 2 && k + 64 >= size; --k) {
    if (data[k - 2] == 0xFF && data[k - 1] == 0xD9) return "";
  }
  return "no JPEG end-of-image marker (truncated frame)";
}

std::vector<TimedEntry> parse_timestamps(const std::string& text, const std::string& what) {
  std::vector<TimedEntry> out;
  std::istringstream lines(text);
  std::string line;
  for (int n = 1; std::getline(lines, line); ++n) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::string time_text;
    if (!(fields >> time_text)) continue;
    TimedEntry e;
    size_t used = 0;
    try {
      e.seconds = std::stod(time_text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != time_text.size() || !std::isfinite(e.seconds)) {
      throw std::runtime_error(what + ":" + std::to_string(n) + ": '" + time_text + "' is no time in seconds");
    }
    fields >> e.file;
    std::string extra;
    if (fields >> extra) throw std::runtime_error(what + ":" + std::to_string(n) + ": expected 'SECONDS [FILE]'");
    if (!out.empty() && !(e.seconds > out.back().seconds)) {
      throw std::runtime_error(what + ":" + std::to_string(n) + ": times must increase");
    }
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace omniview::insta360
