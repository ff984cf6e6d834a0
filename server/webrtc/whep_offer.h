// What a WHEP viewer's SDP offer asks for, read with GStreamer's SDP parser: its first video
// m-line, and the H.264 payload type this daemon answers with.
#pragma once

#include <stdexcept>
#include <string>

namespace omniview::webrtc {

struct H264Offer {
  int payload_type = 0;          // the offer's, echoed in the answer
  std::string profile_level_id;  // as offered (six hex digits), empty when not given
  std::string mid;               // the video m-line's a=mid, empty when not given
  bool nack = false;             // the viewer asked for NACK retransmission (a=rtcp-fb:PT nack)
};

// The offer is fine but holds no H.264 this daemon can send (HTTP 406): the message lists
// what it did offer.
class CodecNotOffered : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Throws std::invalid_argument for an offer that is not SDP, has no video m-line, or whose
// video the viewer would not receive (sendonly, inactive); CodecNotOffered where it has no
// H.264 with packetization-mode=1. Of several H.264 payloads the one whose profile decodes
// the daemon's High-profile stream is preferred: High, then High 4:4:4 (a superset), then
// the first (browsers' decoders take High under any H.264 profile in practice).
H264Offer read_h264_offer(const std::string& sdp);

// `sdp` without its mDNS host candidates (a=candidate lines whose address is a name ending
// in ".local"), as browsers send by default to hide their addresses. The daemon asks no mDNS
// responder, and webrtcbin's ICE agent that was handed one was never freed (a thread and a
// UDP port per address for good after every browser session). ICE connects without them:
// the viewer's checks reaching the daemon's candidates give the daemon its address
// (a peer-reflexive candidate).
std::string without_mdns_candidates(const std::string& sdp);

}  // namespace omniview::webrtc
