// One H.264 video stream: rendered view images in, one Annex-B access unit out per image,
// at once (no frame is held back), with a key frame whenever asked for.
//
// Why libx264 directly: it is the reference-quality H.264 encoder, has a zero-latency tune
// (no B-frames, no lookahead, slice threads: each picture comes out of the call that took
// it), writes Annex-B natively, repeats SPS/PPS before every IDR and makes an IDR on
// demand, which is all a live stream shared by joining and leaving clients needs.
// libavcodec over it adds a layer (and its own frame/packet model) for nothing here;
// OpenH264 gives visibly lower quality per bit at these rates.
//
// Pictures are 4:2:0 (I420), also for grey views (constant mid-grey chroma, which costs
// almost no bits): 4:0:0 is High-profile-only and many decoders (browsers' WebCodecs,
// hardware decoders, most players' fast paths) do not take it. Full-range BT.601, as JPEG,
// so a grey view's luma is its pixel values unchanged.
//
// 4:2:0 needs even sides, and H.264's cropping works in 2-pixel units for 4:2:0 (the SPS
// cannot declare an odd width), so a view of an odd side is coded at the even size that
// covers it, its last column (row) repeated: the picture decodes one pixel wider (taller)
// than the view, and Frame.width/height say the view's own size to crop to. Every view is
// watchable over every H.264 path; a player that ignores Frame shows one repeated edge.
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>

namespace omniview::video {

struct H264Settings {
  int width = 0;
  int height = 0;
  double fps = 15;   // the expected rate: VUI timing and the ceiling's per-frame budget
  double crf = 26;   // constant rate factor, 0..51 (lower: better); the streams' default
  int max_kbps = 0;  // > 0: a ceiling (VBV max rate, one-second buffer) over the CRF
  int threads = 2;   // slice threads: the frame's own latency shrinks, none is added
  // superfast: 2.4 ms a 640x480 frame where veryfast takes 5-6 ms on the 2-core box, for
  // ~1.7x the bits of veryfast at the same CRF (bench/README.md, h264_bench).
  std::string preset = "superfast";
};

// Bounds that any setting must keep; `check` says which one a value breaks.
constexpr int kMinKbps = 50;
constexpr int kMaxKbps = 100000;
constexpr int kMaxSide = 8192;  // H.264 level 6.2's widest picture

// Throws std::invalid_argument naming the field for a setting the encoder cannot use.
void check(const H264Settings& settings);

struct AccessUnit {
  std::string data;  // Annex-B: start codes, SPS and PPS first on a key frame
  bool key_frame = false;
  int64_t pts = 0;
};

class H264Encoder {
 public:
  // Throws std::invalid_argument (bad settings) or std::runtime_error (x264 refused).
  explicit H264Encoder(const H264Settings& settings);
  ~H264Encoder();
  H264Encoder(const H264Encoder&) = delete;
  H264Encoder& operator=(const H264Encoder&) = delete;

  const H264Settings& settings() const { return settings_; }
  // The coded picture: the settings' size rounded up to even sides.
  int coded_width() const { return settings_.width + settings_.width % 2; }
  int coded_height() const { return settings_.height + settings_.height % 2; }

  // `image`: CV_8UC1 (grey) or CV_8UC3 (BGR) of the configured size; `pts_ms`: its time in
  // milliseconds (only its differences matter; made strictly increasing here). A key frame
  // when `key_frame` is set, or where x264 sees a scene cut; no timer of its own (the
  // caller knows when somebody needs one).
  // Throws std::invalid_argument for a wrong size or type, std::runtime_error if x264 fails.
  AccessUnit encode(const cv::Mat& image, int64_t pts_ms, bool key_frame);
  // The rate frames actually come at (a source slower than the stream's rate): keeps the
  // bitrate ceiling a ceiling per second. No effect without a ceiling.
  void set_frame_rate(double fps);

 private:
  struct X264;
  H264Settings settings_;
  std::unique_ptr<X264> x264_;
  cv::Mat yuv_;  // I420: Y, then U, then V planes, one buffer reused frame after frame
  cv::Mat padded_;  // an odd-sided image with its last column/row repeated
  int64_t last_pts_ = INT64_MIN;
  double frame_rate_ = 0;           // what the ceiling is set for
  bool grey_chroma_ready_ = false;  // the U and V planes hold mid-grey already
};

}  // namespace omniview::video
