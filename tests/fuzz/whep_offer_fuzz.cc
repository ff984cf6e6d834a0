// Fuzz target: WHEP offers (the body of POST /whep/VIEW: anyone who reaches the web port with
// a viewer's token sends one). read_h264_offer must answer any input with an offer or
// std::invalid_argument (CodecNotOffered included); the payload type it picks is a valid
// one and the profile (it goes into the media's caps) six hex digits or nothing; taking out
// its mDNS candidates never grows it.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "server/webrtc/whep_offer.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string sdp(reinterpret_cast<const char*>(data), size);
  // Leaving out mDNS candidates only ever removes whole lines.
  if (omniview::webrtc::without_mdns_candidates(sdp).size() > sdp.size()) std::abort();
  try {
    const auto offer = omniview::webrtc::read_h264_offer(sdp);
    if (offer.payload_type < 0 || offer.payload_type > 127) std::abort();
    const auto& p = offer.profile_level_id;
    if (!p.empty() && (p.size() != 6 || p.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)) {
      std::abort();
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
