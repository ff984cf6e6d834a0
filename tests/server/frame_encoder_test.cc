// encode_frame: JPEG through TurboJPEG straight from the view buffer (BGR or grey, any row
// stride), decoded again by core/io's decode_image; PNG and RAW unchanged.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/io/image_codec.h"
#include "server/pipeline/frame_encoder.h"

namespace omniview {
namespace {

// A smooth picture with colour (JPEG's home ground): gradients and a few discs.
cv::Mat test_picture(int w, int h) {
  cv::Mat img(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) img.at<cv::Vec3b>(y, x) = cv::Vec3b(x * 255 / w, y * 255 / h, (x + y) * 127 / (w + h));
  }
  cv::circle(img, {w / 3, h / 2}, h / 4, cv::Scalar(20, 200, 240), -1, cv::LINE_AA);
  cv::circle(img, {2 * w / 3, h / 3}, h / 5, cv::Scalar(230, 40, 60), -1, cv::LINE_AA);
  return img;
}

cv::Mat decode(const v1::Frame& frame) {
  return decode_image(frame.data());
}

TEST(FrameEncoder, ColourJpegKeepsBgrOrder) {
  const cv::Mat img = test_picture(160, 96);
  v1::Frame frame;
  encode_frame(img, encoding_key(v1::JPEG, 90, false), frame);
  EXPECT_EQ(frame.encoding(), v1::JPEG);
  EXPECT_EQ(frame.width(), 160u);
  EXPECT_EQ(frame.height(), 96u);
  EXPECT_EQ(frame.channels(), 3u);
  const cv::Mat back = decode(frame);
  ASSERT_EQ(back.type(), CV_8UC3);
  EXPECT_GT(cv::PSNR(back, img), 32);  // a swapped R and B would fall far below
  cv::Mat swapped;
  cv::cvtColor(img, swapped, cv::COLOR_BGR2RGB);
  EXPECT_LT(cv::PSNR(back, swapped), 25);
}

TEST(FrameEncoder, GreyStaysGreyAndGreyKeyGivesLuma) {
  const cv::Mat colour = test_picture(128, 64);
  cv::Mat grey;
  cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
  for (const cv::Mat& img : {grey, colour}) {
    v1::Frame frame;
    encode_frame(img, encoding_key(v1::JPEG, 90, true), frame);
    EXPECT_EQ(frame.channels(), 1u);
    const cv::Mat back = decode(frame);
    ASSERT_EQ(back.type(), CV_8UC1);
    EXPECT_GT(cv::PSNR(back, grey), 35);
  }
  v1::Frame frame;  // a grey view without the grey key is still one channel
  encode_frame(grey, encoding_key(v1::JPEG, 0, false), frame);
  EXPECT_EQ(frame.channels(), 1u);
  EXPECT_EQ(decode(frame).type(), CV_8UC1);
}

TEST(FrameEncoder, RowsAtTheImagesOwnStride) {
  const cv::Mat big = test_picture(300, 200);
  const cv::Mat roi = big(cv::Rect(17, 11, 161, 93));  // odd size, not continuous
  ASSERT_FALSE(roi.isContinuous());
  v1::Frame frame;
  encode_frame(roi, encoding_key(v1::JPEG, 95, false), frame);
  const cv::Mat back = decode(frame);
  ASSERT_EQ(back.size(), roi.size());
  EXPECT_GT(cv::PSNR(back, roi), 32);
}

TEST(FrameEncoder, QualityChangesSize) {
  const cv::Mat img = test_picture(256, 128);
  v1::Frame low, high;
  encode_frame(img, encoding_key(v1::JPEG, 20, false), low);
  encode_frame(img, encoding_key(v1::JPEG, 98, false), high);
  EXPECT_LT(low.data().size(), high.data().size());
}

TEST(FrameEncoder, PngAndRawAreLossless) {
  const cv::Mat img = test_picture(64, 48);
  v1::Frame png, raw;
  encode_frame(img, encoding_key(v1::PNG, 0, false), png);
  EXPECT_EQ(cv::norm(decode(png), img, cv::NORM_INF), 0);
  encode_frame(img, encoding_key(v1::RAW, 0, false), raw);
  ASSERT_EQ(raw.data().size(), 64u * 48u * 3u);
  EXPECT_EQ(static_cast<uint8_t>(raw.data()[0]), img.at<cv::Vec3b>(0, 0)[2]);  // RAW is RGB
}

}  // namespace
}  // namespace omniview
