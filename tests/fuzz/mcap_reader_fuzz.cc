// Fuzz target: the MCAP reader (core/mcap), which reads exported files and files cut short.
// Input: the bytes of an MCAP file. McapError is the expected answer to bad input; anything
// else (a crash, a sanitizer report, a broken promise of the result) is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "core/mcap/mcap_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  omniview::mcap::ReadOptions options;
  options.max_chunk_bytes = 16 << 20;  // a claimed size is never allocated beyond this
  try {
    const auto contents = omniview::mcap::read_mcap(input, "fuzz", options);
    // What the reader promises: every message on a channel it defined, a cut within the file.
    for (const auto& m : contents.messages) {
      if (!contents.channels.count(m.channel)) std::abort();
    }
    if (!contents.complete && contents.cut_at > size) std::abort();
    for (const auto& r : contents.records) {
      if (r.offset + 9 + r.length > size) std::abort();
    }
  } catch (const omniview::mcap::McapError&) {
  }
  return 0;
}
