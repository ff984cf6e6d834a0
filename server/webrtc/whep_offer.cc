#include "server/webrtc/whep_offer.h"

#include <gst/sdp/sdp.h>

#include <algorithm>
#include <cctype>
#include <memory>
#include <set>
#include <sstream>
#include <string_view>

namespace omniview::webrtc {
namespace {

using SdpMessage = std::unique_ptr<GstSDPMessage, decltype(&gst_sdp_message_free)>;

// "packetization-mode=1;profile-level-id=42e01f" -> the value of `key`, "" when absent.
std::string fmtp_value(const std::string& fmtp, const std::string& key) {
  std::istringstream in(fmtp);
  std::string part;
  while (std::getline(in, part, ';')) {
    const auto start = part.find_first_not_of(' ');
    if (start == std::string::npos) continue;
    part = part.substr(start);
    if (part.rfind(key + "=", 0) == 0) return part.substr(key.size() + 1);
  }
  return "";
}

// The attribute `name` of `media` for payload type `pt` ("a=fmtp:PT VALUE" -> VALUE).
std::string payload_attribute(const GstSDPMedia* media, const char* name, int pt) {
  const std::string prefix = std::to_string(pt) + " ";
  for (guint i = 0; i < gst_sdp_media_attributes_len(media); ++i) {
    const GstSDPAttribute* a = gst_sdp_media_get_attribute(media, i);
    if (a->key == nullptr || a->value == nullptr || std::string(a->key) != name) continue;
    const std::string value = a->value;
    if (value.rfind(prefix, 0) == 0) return value.substr(prefix.size());
  }
  return "";
}

bool has_rtcp_fb(const GstSDPMedia* media, int pt, const std::string& feedback) {
  const std::string prefix = std::to_string(pt) + " ";
  for (guint i = 0; i < gst_sdp_media_attributes_len(media); ++i) {
    const GstSDPAttribute* a = gst_sdp_media_get_attribute(media, i);
    if (a->key == nullptr || a->value == nullptr || std::string(a->key) != "rtcp-fb") continue;
    if (std::string(a->value) == prefix + feedback) return true;
  }
  return false;
}

// High (0x64) first, High 4:4:4 Predictive (0xf4, whose decoders take High) next, Main
// (0x4d) next, then any other.
int profile_rank(const std::string& profile_level_id) {
  const std::string idc = profile_level_id.substr(0, 2);
  if (idc == "64") return 0;
  if (idc == "f4" || idc == "F4") return 1;
  if (idc == "4d" || idc == "4D") return 2;
  return 3;
}

// GStreamer's parser reads an m-line's port with atoi ("m=video foo" is port 0, "rejected"):
// the first video m-line's port and protocol are checked as text here.
void check_video_line(const std::string& sdp) {
  std::istringstream lines(sdp);
  std::string line;
  while (std::getline(lines, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.rfind("m=video ", 0) != 0) continue;
    std::istringstream fields(line.substr(8));
    std::string port, proto;
    fields >> port >> proto;
    const std::string digits = port.substr(0, port.find('/'));  // "9/2": a port count
    if (digits.empty() || digits.size() > 5 || digits.find_first_not_of("0123456789") != std::string::npos ||
        std::stoi(digits) > 65535 || proto.empty()) {
      throw std::invalid_argument("the offer's video m-line is malformed ('" + line.substr(0, 80) +
                                  "'): 'm=video PORT UDP/TLS/RTP/SAVPF PAYLOAD-TYPES' expected");
    }
    return;
  }
}

}  // namespace

H264Offer read_h264_offer(const std::string& sdp) {
  if (sdp.empty()) throw std::invalid_argument("the request has no SDP offer in its body");
  // GStreamer's parser reads a C string (a NUL ends it early, and one at the start made it
  // write a CRITICAL into the daemon's log for any client that sent one).
  if (sdp.find('\0') != std::string::npos) throw std::invalid_argument("the body is not an SDP offer (a NUL byte in it)");
  GstSDPMessage* raw = nullptr;
  if (gst_sdp_message_new_from_text(sdp.c_str(), &raw) != GST_SDP_OK || raw == nullptr) {
    throw std::invalid_argument("the body is not an SDP offer");
  }
  const SdpMessage message(raw, &gst_sdp_message_free);
  if (gst_sdp_message_medias_len(raw) == 0) {
    throw std::invalid_argument("the body is not an SDP offer with media (no m= line)");
  }
  const GstSDPMedia* video = nullptr;
  for (guint i = 0; i < gst_sdp_message_medias_len(raw) && video == nullptr; ++i) {
    const GstSDPMedia* m = gst_sdp_message_get_media(raw, i);
    if (gst_sdp_media_get_media(m) != nullptr && std::string(gst_sdp_media_get_media(m)) == "video") video = m;
  }
  if (video == nullptr) throw std::invalid_argument("the offer has no video m-line: a view is video only");
  check_video_line(sdp);
  if (gst_sdp_media_get_port(video) == 0) throw std::invalid_argument("the offer's video m-line is rejected (port 0)");
  if (gst_sdp_media_get_attribute_val(video, "sendonly") != nullptr ||
      gst_sdp_media_get_attribute_val(video, "inactive") != nullptr) {
    throw std::invalid_argument("the offer's video is sendonly or inactive: a WHEP viewer receives (recvonly)");
  }
  const char* proto = gst_sdp_media_get_proto(video);
  if (proto == nullptr || std::string(proto).find("SAVPF") == std::string::npos) {
    throw std::invalid_argument(std::string("the offer's video uses '") + (proto ? proto : "") +
                                "', not WebRTC's UDP/TLS/RTP/SAVPF");
  }
  H264Offer best;
  int best_rank = 4;
  std::set<std::string> offered;
  for (guint i = 0; i < gst_sdp_media_formats_len(video); ++i) {
    const char* format = gst_sdp_media_get_format(video, i);
    int pt = -1;
    try {
      pt = std::stoi(format ? format : "");
    } catch (const std::exception&) {
      continue;
    }
    if (pt < 0 || pt > 127) continue;
    // GStreamer's payloaders send dynamic payload types only (96-127): Chromium lists
    // High 4:4:4 as 41, outside them.
    const bool sendable = pt >= 96;
    const std::string rtpmap = payload_attribute(video, "rtpmap", pt);
    const std::string codec = rtpmap.substr(0, rtpmap.find('/'));
    const std::string fmtp = payload_attribute(video, "fmtp", pt);
    const bool mode_1 = fmtp_value(fmtp, "packetization-mode") == "1";
    if (!codec.empty() && codec != "rtx" && codec != "red" && codec != "ulpfec") {
      // Named as what it lacks where that is why it is not taken.
      offered.insert(codec == "H264" && !mode_1 ? "H264 without packetization-mode=1"
                     : codec == "H264" && !sendable ? "H264 in payload type " + std::to_string(pt)
                                                    : codec);
    }
    if (rtpmap != "H264/90000" || !sendable || !mode_1) continue;
    std::string profile = fmtp_value(fmtp, "profile-level-id");
    // Six hex digits (RFC 6184), or taken as not given: it goes into the media's caps.
    if (profile.size() != 6 || profile.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) profile.clear();
    const int rank = profile_rank(profile);
    if (rank >= best_rank) continue;
    best_rank = rank;
    best.payload_type = pt;
    best.profile_level_id = profile;
    best.nack = has_rtcp_fb(video, pt, "nack");
  }
  if (best_rank == 4 && offered.empty() && gst_sdp_media_formats_len(video) > 0) {
    // Payload types listed, none described: not "no H.264" but an offer cut short.
    throw std::invalid_argument("the offer's video lists payload types but no a=rtpmap line for any (a truncated "
                                "offer?)");
  }
  if (best_rank == 4) {
    std::string list;
    for (const auto& c : offered) list += (list.empty() ? "" : ", ") + c;
    throw CodecNotOffered("the offer has no H.264 with packetization-mode=1 and a dynamic payload type (offered: " +
                          (list.empty() ? std::string("nothing") : list) +
                          "); this daemon sends its views as H.264 only");
  }
  if (const char* mid = gst_sdp_media_get_attribute_val(video, "mid")) best.mid = mid;
  return best;
}

std::string without_mdns_candidates(const std::string& sdp) {
  std::string out;
  out.reserve(sdp.size());
  size_t start = 0;
  while (start < sdp.size()) {
    size_t end = sdp.find('\n', start);
    end = end == std::string::npos ? sdp.size() : end + 1;
    const std::string_view line(sdp.data() + start, end - start);
    bool mdns = false;
    if (line.rfind("a=candidate:", 0) == 0) {
      // foundation component transport priority ADDRESS port typ ...
      std::istringstream fields{std::string(line.substr(12))};
      std::string field, address;
      for (int i = 0; i < 5 && fields >> field; ++i) address = field;
      std::transform(address.begin(), address.end(), address.begin(), [](unsigned char c) { return std::tolower(c); });
      mdns = address.size() > 6 && address.compare(address.size() - 6, 6, ".local") == 0;
    }
    if (!mdns) out.append(line);
    start = end;
  }
  return out;
}

}  // namespace omniview::webrtc
