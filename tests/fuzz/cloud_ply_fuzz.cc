// Fuzz target: a PLY point cloud file (offline colouring input, replay). CloudFormatError
// naming the problem is the expected answer to bad input; a crash, a hang, any other
// exception or fields whose lengths disagree with the point count is a bug. Whatever
// parses must also write and read back.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "core/cloud/cloud_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto cloud = omniview::parse_ply(text, "fuzz.ply");
    cloud.check("fuzz.ply");
    const auto again = omniview::parse_ply(omniview::format_ply(cloud), "again.ply");
    if (again.size() != cloud.size()) std::abort();
  } catch (const omniview::CloudFormatError&) {
  }
  return 0;
}
