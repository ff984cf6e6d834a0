// Fuzz target: VLP-16 UDP payloads (anyone on the lidar's network can send them). The input
// is cut into 1206-byte packets (the rest is one short packet) fed to one assembler, in
// single and dual return modes. CloudFormatError naming the problem is the expected answer
// to bad input; a crash, a hang, any other exception, a non-finite point or fields whose
// lengths disagree is a bug.
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "core/cloud/vlp16.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace omniview;
  Vlp16Assembler assembler(Vlp16Calibration{}, "fuzz", size % 2 ? Vlp16Returns::kAll : Vlp16Returns::kStrongest);
  const auto received = std::chrono::system_clock::time_point(std::chrono::hours(490000));
  for (size_t at = 0; at < size; at += kVlp16PacketSize) {
    const size_t n = std::min(kVlp16PacketSize, size - at);
    try {
      for (const auto& cloud : assembler.add_packet(data + at, n, received, "fuzz")) {
        cloud.check("fuzz");
        if (cloud.time.size() != cloud.size() || cloud.ring.size() != cloud.size()) std::abort();
        for (const auto& p : cloud.points) {
          if (!p.allFinite()) std::abort();
        }
      }
    } catch (const CloudFormatError&) {
    }
  }
  return 0;
}
