// The WHEP offer reader (server/webrtc/whep_offer.h) on real offers (Chromium's, aiortc's:
// the fuzz corpus's seeds) and on what a viewer must not send.
#include "server/webrtc/whep_offer.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace omniview::webrtc {
namespace {

std::string seed(const std::string& name) {
  std::ifstream in(std::string(OMNIVIEW_SOURCE_DIR) + "/tests/fuzz/corpus/whep_offer/" + name);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(WhepOffer, ChromiumsOfferGetsTheProfileThatDecodesHighWithNack) {
  const std::string sdp = seed("chromium_audio_video.sdp");
  ASSERT_FALSE(sdp.empty());
  const H264Offer offer = read_h264_offer(sdp);
  // Chromium offers no plain High, and High 4:4:4 only as payload type 41, which GStreamer's
  // payloader cannot send (96-127 only): Main.
  EXPECT_EQ(offer.profile_level_id.substr(0, 2), "4d");
  EXPECT_GE(offer.payload_type, 96);
  EXPECT_NE(sdp.find("a=rtpmap:" + std::to_string(offer.payload_type) + " H264/90000"), std::string::npos);
  EXPECT_TRUE(offer.nack);
  EXPECT_EQ(offer.mid, "0");
}

TEST(WhepOffer, AiortcsOfferGetsItsFirstH264) {
  const H264Offer offer = read_h264_offer(seed("aiortc_video.sdp"));
  EXPECT_EQ(offer.profile_level_id.substr(0, 2), "42");
  EXPECT_TRUE(offer.nack);
}

TEST(WhepOffer, AProfileThatIsNotSixHexDigitsIsTakenAsNotGiven) {
  // It would go into the media's caps: never text of the viewer's choosing.
  const H264Offer offer = read_h264_offer(seed("odd_profile.sdp"));
  EXPECT_EQ(offer.payload_type, 97);
  EXPECT_EQ(offer.profile_level_id, "");
}

TEST(WhepOffer, MdnsCandidatesAreLeftOutAndTheRestKept) {
  const std::string offer =
      "v=0\r\nm=video 9 UDP/TLS/RTP/SAVPF 96\r\n"
      "a=candidate:1 1 udp 2122260223 0b2c1d3e-4f50-4a6b-8c7d-9e0f1a2b3c4d.local 54321 typ host generation 0\r\n"
      "a=candidate:2 1 udp 2122260223 192.168.1.20 54322 typ host\r\n"
      "a=candidate:3 1 UDP 1686052607 ABC.LOCAL 54323 typ srflx raddr 0.0.0.0 rport 0\r\n"
      "a=candidate:4 1 udp 1 local 54324 typ host\n"  // a host named "local": kept
      "a=mid:0\r\n";
  EXPECT_EQ(without_mdns_candidates(offer),
            "v=0\r\nm=video 9 UDP/TLS/RTP/SAVPF 96\r\n"
            "a=candidate:2 1 udp 2122260223 192.168.1.20 54322 typ host\r\n"
            "a=candidate:4 1 udp 1 local 54324 typ host\n"
            "a=mid:0\r\n");
  EXPECT_EQ(without_mdns_candidates(""), "");
  EXPECT_EQ(without_mdns_candidates("a=candidate:1 1 udp"), "a=candidate:1 1 udp");  // cut short: kept
}

TEST(WhepOffer, BadOffersSayWhatIsWrong) {
  const std::string head = "v=0\r\no=- 1 1 IN IP4 127.0.0.1\r\ns=-\r\nt=0 0\r\n";
  const auto message = [](const std::string& sdp) -> std::string {
    try {
      read_h264_offer(sdp);
    } catch (const CodecNotOffered& e) {
      return std::string("406 ") + e.what();
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(message(""), "the request has no SDP offer in its body");
  EXPECT_EQ(message(head), "the body is not an SDP offer with media (no m= line)");
  EXPECT_EQ(message(head + "m=audio 9 UDP/TLS/RTP/SAVPF 111\r\na=rtpmap:111 opus/48000/2\r\n"),
            "the offer has no video m-line: a view is video only");
  EXPECT_EQ(message(head + "m=video 0 UDP/TLS/RTP/SAVPF 96\r\n"), "the offer's video m-line is rejected (port 0)");
  EXPECT_NE(message(head + "m=video 9 UDP/TLS/RTP/SAVPF 96\r\na=sendonly\r\n").find("recvonly"), std::string::npos);
  EXPECT_NE(message(head + "m=video 9 RTP/AVP 96\r\n").find("SAVPF"), std::string::npos);
  EXPECT_EQ(message(head + "m=video 9 UDP/TLS/RTP/SAVPF 96 97 98\r\na=rtpmap:96 VP8/90000\r\na=rtpmap:97 "
                           "rtx/90000\r\na=rtpmap:98 H264/90000\r\na=fmtp:98 packetization-mode=0\r\n"),
            "406 the offer has no H.264 with packetization-mode=1 and a dynamic payload type (offered: H264 without "
            "packetization-mode=1, VP8); "
            "this daemon sends its views as H.264 only");
  EXPECT_EQ(message(std::string("\0v=0\r\n", 7)), "the body is not an SDP offer (a NUL byte in it)");
  // GStreamer's parser reads "foo" as port 0: said as malformed, not as rejected.
  EXPECT_EQ(message(head + "m=video foo bar\r\n").substr(0, 44), "the offer's video m-line is malformed ('m=vi");
  EXPECT_NE(message(head + "m=video 70000 UDP/TLS/RTP/SAVPF 96\r\n").find("malformed"), std::string::npos);
  // Cut short after the m-line: no rtpmap for its payload types. Not "no H.264" (a 406).
  const std::string truncated = seed("aiortc_video.sdp").substr(0, seed("aiortc_video.sdp").find("a=rtpmap"));
  EXPECT_EQ(message(truncated).substr(0, 60), "the offer's video lists payload types but no a=rtpmap line f");
}

}  // namespace
}  // namespace omniview::webrtc
