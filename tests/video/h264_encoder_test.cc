// The H.264 wrapper (server/video) against a real decoder (libavcodec): sizes, grey and
// colour pictures, key frames on request, the low-latency contract (every picture comes out
// of its own call) and the bitrate ceiling.
#include "server/video/h264_encoder.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "tests/video/h264_decoder.h"

namespace omniview::testing {
namespace {

using video::AccessUnit;
using video::H264Encoder;
using video::H264Settings;

// A scene with edges, gradients and texture; `t` moves it (a camera panning).
cv::Mat scene(int width, int height, int t, bool colour) {
  cv::Mat img(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int u = x + 3 * t;
      img.at<cv::Vec3b>(y, x) = {static_cast<uint8_t>((u * 2 + y) & 0xff),
                                 static_cast<uint8_t>(((u / 16 + y / 16) % 2) * 160 + 40),
                                 static_cast<uint8_t>(128 + 100 * std::sin(u * 0.05) * std::cos(y * 0.04))};
    }
  }
  cv::circle(img, {width / 3 + t, height / 2}, std::max(2, height / 5), {20, 220, 90}, -1);
  if (colour) return img;
  cv::Mat grey;
  cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY);
  return grey;
}

H264Settings settings(int width, int height) {
  H264Settings s;
  s.width = width;
  s.height = height;
  s.fps = 15;
  return s;
}

// NAL unit types in an Annex-B access unit, in order.
std::vector<int> nal_types(const std::string& au) {
  std::vector<int> types;
  for (size_t i = 0; i + 3 < au.size(); ++i) {
    if (au[i] == 0 && au[i + 1] == 0 && au[i + 2] == 1) {
      types.push_back(au[i + 3] & 0x1f);
      i += 3;
    }
  }
  return types;
}

TEST(H264Encoder, GreyPicturesDecodeCloseToTheOriginalWithConstantChroma) {
  H264Encoder encoder(settings(640, 480));
  H264Decoder decoder;
  for (int t = 0; t < 10; ++t) {
    const cv::Mat image = scene(640, 480, t, false);
    const AccessUnit au = encoder.encode(image, t * 66, false);
    ASSERT_FALSE(au.data.empty()) << "frame " << t << " held back";
    EXPECT_EQ(au.key_frame, t == 0) << t;
    const cv::Mat picture = decoder.decode(au.data);
    ASSERT_FALSE(picture.empty()) << "frame " << t << ": " << decoder.last_error();
    EXPECT_TRUE(decoder.full_range());
    EXPECT_GT(psnr(H264Decoder::luma(picture, 640, 480), image), 38) << t;
    // Chroma is mid-grey everywhere (a grey picture in 4:2:0).
    const cv::Mat chroma = picture.rowRange(480, 720);
    double lo = 0, hi = 0;
    cv::minMaxLoc(chroma, &lo, &hi);
    EXPECT_GE(lo, 127) << t;
    EXPECT_LE(hi, 129) << t;
  }
  EXPECT_EQ(decoder.errors(), 0) << decoder.last_error();
}

TEST(H264Encoder, ColourPicturesKeepTheirColours) {
  H264Encoder encoder(settings(320, 240));
  H264Decoder decoder;
  const cv::Mat image = scene(320, 240, 0, true);
  const cv::Mat picture = decoder.decode(encoder.encode(image, 0, false).data);
  ASSERT_FALSE(picture.empty()) << decoder.last_error();
  cv::Mat bgr;
  // Full-range BT.601 back to BGR, as JPEG's YCbCr: rebuild YCrCb at full size.
  cv::Mat y = H264Decoder::luma(picture, 320, 240);
  cv::Mat u(120, 160, CV_8UC1, picture.data + 320 * 240);
  cv::Mat v(120, 160, CV_8UC1, picture.data + 320 * 240 * 5 / 4);
  cv::Mat cb, cr;
  cv::resize(u, cb, y.size(), 0, 0, cv::INTER_LINEAR);
  cv::resize(v, cr, y.size(), 0, 0, cv::INTER_LINEAR);
  cv::Mat ycrcb;
  cv::merge(std::vector<cv::Mat>{y, cr, cb}, ycrcb);
  cv::cvtColor(ycrcb, bgr, cv::COLOR_YCrCb2BGR);
  // The green disc stays green.
  const cv::Vec3b centre = bgr.at<cv::Vec3b>(120, 320 / 3);
  EXPECT_NEAR(centre[0], 20, 12);
  EXPECT_NEAR(centre[1], 220, 12);
  EXPECT_NEAR(centre[2], 90, 12);
  // Planes as full-range BT.601 (JPEG's YCbCr) gives them, chroma averaged per 2x2 block:
  // what 4:2:0 can carry, and the codec keeps it closely.
  cv::Mat want_ycrcb;
  cv::cvtColor(image, want_ycrcb, cv::COLOR_BGR2YCrCb);
  std::vector<cv::Mat> want;
  cv::split(want_ycrcb, want);
  cv::Mat want_cb, want_cr;
  cv::resize(want[2], want_cb, u.size(), 0, 0, cv::INTER_AREA);
  cv::resize(want[1], want_cr, v.size(), 0, 0, cv::INTER_AREA);
  EXPECT_GT(psnr(y, want[0]), 35);
  EXPECT_GT(psnr(u, want_cb), 35);
  EXPECT_GT(psnr(v, want_cr), 35);
}

TEST(H264Encoder, KeyFrameOnRequestCarriesSpsAndPps) {
  H264Encoder encoder(settings(320, 240));
  H264Decoder late_joiner;
  for (int t = 0; t < 12; ++t) {
    const bool ask = t == 7;
    const AccessUnit au = encoder.encode(scene(320, 240, t, false), t * 66, ask);
    const auto types = nal_types(au.data);
    ASSERT_FALSE(types.empty());
    if (t == 0 || ask) {
      EXPECT_TRUE(au.key_frame) << t;
      // SPS (7) and PPS (8) before the IDR slice (5).
      EXPECT_NE(std::find(types.begin(), types.end(), 7), types.end()) << t;
      EXPECT_NE(std::find(types.begin(), types.end(), 8), types.end()) << t;
      EXPECT_NE(std::find(types.begin(), types.end(), 5), types.end()) << t;
    } else {
      EXPECT_FALSE(au.key_frame) << t;
      EXPECT_EQ(std::find(types.begin(), types.end(), 5), types.end()) << t;
      EXPECT_EQ(std::find(types.begin(), types.end(), 7), types.end()) << t;
    }
    // A decoder that starts at the requested key frame decodes everything from there.
    if (t >= 7) {
      EXPECT_FALSE(late_joiner.decode(au.data).empty()) << t << ": " << late_joiner.last_error();
    }
  }
  EXPECT_EQ(late_joiner.errors(), 0) << late_joiner.last_error();
}

TEST(H264Encoder, AbsurdSizesAreRefusedClearly) {
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{0, 480}, {-2, 2}, {16384, 16}, {640, 100000}}) {
    try {
      H264Encoder encoder(settings(w, h));
      ADD_FAILURE() << w << "x" << h << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(std::to_string(w) + "x" + std::to_string(h)), std::string::npos) << e.what();
    }
  }
}

TEST(H264Encoder, TinyAndUnalignedEvenSizesRoundTrip) {
  // Not multiples of 16: x264 pads to macroblocks and crops in the SPS.
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{2, 2}, {18, 10}, {642, 482}}) {
    H264Encoder encoder(settings(w, h));
    H264Decoder decoder;
    const cv::Mat image = scene(w, h, 0, false);
    const cv::Mat picture = decoder.decode(encoder.encode(image, 0, false).data);
    ASSERT_EQ(picture.cols, w) << decoder.last_error();
    ASSERT_EQ(picture.rows, h * 3 / 2);
    EXPECT_GT(psnr(H264Decoder::luma(picture, w, h), image), 30) << w << "x" << h;
  }
}

// 4:2:0 cannot declare an odd side (the SPS crops in 2-pixel units): such a picture is
// coded at the even size that covers it, its last column/row repeated (h264_encoder.h).
TEST(H264Encoder, OddSizesAreCodedOnePixelLargerWithTheEdgeRepeated) {
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {641, 480}, {640, 479}, {81, 61}}) {
    H264Encoder encoder(settings(w, h));
    const int cw = w + w % 2, ch = h + h % 2;
    EXPECT_EQ(encoder.coded_width(), cw);
    EXPECT_EQ(encoder.coded_height(), ch);
    H264Decoder decoder;
    const cv::Mat image = scene(w, h, 0, false);
    const cv::Mat picture = decoder.decode(encoder.encode(image, 0, false).data);
    ASSERT_EQ(picture.cols, cw) << decoder.last_error();
    ASSERT_EQ(picture.rows, ch * 3 / 2);
    cv::Mat expected;
    cv::copyMakeBorder(image, expected, 0, ch - h, 0, cw - w, cv::BORDER_REPLICATE);
    EXPECT_GT(psnr(H264Decoder::luma(picture, cw, ch), expected), 30) << w << "x" << h;
  }
}

TEST(H264Encoder, WrongImagesAndSettingsAreErrorsNotCrashes) {
  H264Encoder encoder(settings(64, 48));
  EXPECT_THROW(encoder.encode(cv::Mat(48, 62, CV_8UC1, cv::Scalar(0)), 0, false), std::invalid_argument);
  EXPECT_THROW(encoder.encode(cv::Mat(48, 64, CV_16UC1, cv::Scalar(0)), 0, false), std::invalid_argument);
  EXPECT_THROW(encoder.encode(cv::Mat(), 0, false), std::invalid_argument);
  H264Settings s = settings(64, 48);
  s.max_kbps = 10;
  EXPECT_THROW(H264Encoder{s}, std::invalid_argument);
  s.max_kbps = 0;
  s.crf = 60;
  EXPECT_THROW(H264Encoder{s}, std::invalid_argument);
  s.crf = 23;
  s.preset = "no-such-preset";
  EXPECT_THROW(H264Encoder{s}, std::invalid_argument);
  // Time stamps that repeat or go back still give a frame each.
  EXPECT_FALSE(encoder.encode(scene(64, 48, 0, false), 100, false).data.empty());
  EXPECT_FALSE(encoder.encode(scene(64, 48, 1, false), 100, false).data.empty());
  EXPECT_FALSE(encoder.encode(scene(64, 48, 2, false), 50, false).data.empty());
}

TEST(H264Encoder, BitrateCeilingHolds) {
  // Noise is the worst case: at CRF 23 it costs many times the ceiling.
  H264Settings s = settings(320, 240);
  s.max_kbps = 300;
  H264Encoder capped(s);
  H264Encoder free(settings(320, 240));
  cv::RNG rng(7);
  size_t capped_bytes = 0, free_bytes = 0;
  const int frames = 45;  // 3 s at 15 fps
  for (int t = 0; t < frames; ++t) {
    cv::Mat noise(240, 320, CV_8UC1);
    rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
    capped_bytes += capped.encode(noise, t * 1000 / 15, false).data.size();
    free_bytes += free.encode(noise, t * 1000 / 15, false).data.size();
  }
  const double capped_kbps = capped_bytes * 8.0 / 1000 / (frames / 15.0);
  const double free_kbps = free_bytes * 8.0 / 1000 / (frames / 15.0);
  EXPECT_GT(free_kbps, 3 * s.max_kbps);
  // The one-second buffer starts full: over 3 s at most the ceiling plus that second.
  EXPECT_LT(capped_kbps, s.max_kbps * 1.5) << "uncapped: " << free_kbps;
}

}  // namespace
}  // namespace omniview::testing
