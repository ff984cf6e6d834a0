// core/io/image_codec: PNG and JPEG through libpng and libjpeg-turbo, in memory and on disk,
// and the errors a user sees for files that are not images.
#include "core/io/image_codec.h"

#include <turbojpeg.h>
#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "tests/core/test_support.h"

namespace omniview {
namespace {

namespace fs = std::filesystem;

// A smooth picture with detail in every channel, so a swapped channel or a shifted row shows.
cv::Mat picture(int width, int height, int type) {
  cv::Mat out(height, width, type);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const auto b = cv::saturate_cast<uint8_t>(128 + 100 * std::sin(u * 0.11));
      const auto g = cv::saturate_cast<uint8_t>(128 + 100 * std::cos(v * 0.07));
      const auto r = cv::saturate_cast<uint8_t>(128 + 100 * std::sin((u + 2 * v) * 0.05));
      if (type == CV_8UC1) {
        out.at<uint8_t>(v, u) = b;
      } else {
        out.at<cv::Vec3b>(v, u) = cv::Vec3b(b, g, r);
      }
    }
  }
  return out;
}

double max_difference(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_INF); }

double psnr(const cv::Mat& a, const cv::Mat& b) { return cv::PSNR(a, b); }

const std::string kCorpus = OMNIVIEW_SOURCE_DIR "/tests/fuzz/corpus/image/";

// The offset of the first JPEG marker `code` (0xFF code) in `jpeg`.
size_t marker(const std::vector<uint8_t>& jpeg, uint8_t code) {
  for (size_t i = 0; i + 1 < jpeg.size(); ++i) {
    if (jpeg[i] == 0xff && jpeg[i + 1] == code) return i;
  }
  ADD_FAILURE() << "no marker " << int(code);
  return 0;
}

void put_u16(std::vector<uint8_t>& b, size_t at, unsigned value) {
  b[at] = uint8_t(value >> 8);
  b[at + 1] = uint8_t(value);
}

TEST(ImageCodec, PngKeepsGreyAndColourExactly) {
  for (const int type : {CV_8UC1, CV_8UC3}) {
    const cv::Mat original = picture(97, 61, type);  // odd sizes: no row padding assumed
    const std::vector<uint8_t> png = encode_png(original);
    const cv::Mat back = decode_image(png);
    ASSERT_EQ(back.type(), type);
    ASSERT_EQ(back.size(), original.size());
    EXPECT_EQ(max_difference(back, original), 0) << "type " << type;
  }
}

TEST(ImageCodec, JpegKeepsTheChannelOrderAndIsCloseAtHighQuality) {
  const cv::Mat colour = picture(160, 96, CV_8UC3);
  const cv::Mat back = decode_image(encode_jpeg(colour, 95));
  ASSERT_EQ(back.type(), CV_8UC3);
  EXPECT_GT(psnr(back, colour), 35);
  // Each channel against the original's same channel, and clearly not another's.
  std::vector<cv::Mat> a, b;
  cv::split(colour, a);
  cv::split(back, b);
  EXPECT_GT(psnr(b[0], a[0]), 35);
  EXPECT_LT(psnr(b[0], a[2]), 20) << "blue and red swapped";

  const cv::Mat grey = picture(160, 96, CV_8UC1);
  const cv::Mat grey_back = decode_image(encode_jpeg(grey, 95));
  ASSERT_EQ(grey_back.type(), CV_8UC1) << "a grey JPEG stays grey";
  EXPECT_GT(psnr(grey_back, grey), 35);
}

TEST(ImageCodec, LowerQualityGivesSmallerJpegs) {
  const cv::Mat colour = picture(320, 240, CV_8UC3);
  EXPECT_LT(encode_jpeg(colour, 40).size(), encode_jpeg(colour, 95).size());
  EXPECT_THROW(encode_jpeg(colour, 0), std::invalid_argument);
  EXPECT_THROW(encode_jpeg(colour, 101), std::invalid_argument);
}

TEST(ImageCodec, ARegionOfALargerImageEncodesItsOwnPixels) {
  const cv::Mat whole = picture(200, 120, CV_8UC3);
  const cv::Mat region = whole(cv::Rect(13, 7, 101, 55));  // rows a stride apart
  ASSERT_FALSE(region.isContinuous());
  EXPECT_EQ(max_difference(decode_image(encode_png(region)), region), 0);
  EXPECT_GT(psnr(decode_image(encode_jpeg(region, 95)), region.clone()), 35);
}

TEST(ImageCodec, AskedColourIsGiven) {
  const cv::Mat colour = picture(64, 48, CV_8UC3);
  const std::vector<uint8_t> png = encode_png(colour);
  const cv::Mat grey = decode_image(png, ImageColour::kGrey);
  ASSERT_EQ(grey.type(), CV_8UC1);
  cv::Mat expected;
  cv::cvtColor(colour, expected, cv::COLOR_BGR2GRAY);
  EXPECT_LE(max_difference(grey, expected), 1);
  const cv::Mat from_grey = decode_image(encode_png(expected), ImageColour::kBgr);
  ASSERT_EQ(from_grey.type(), CV_8UC3);
  std::vector<cv::Mat> channels;
  cv::split(from_grey, channels);
  EXPECT_EQ(max_difference(channels[0], expected), 0);
  EXPECT_EQ(max_difference(channels[2], expected), 0);
  EXPECT_EQ(decode_image(encode_jpeg(colour, 90), ImageColour::kGrey).type(), CV_8UC1);
}

TEST(ImageCodec, BadBytesGiveAnEmptyImageAndAReason) {
  std::string why;
  EXPECT_TRUE(decode_image(std::string("not an image at all"), ImageColour::kAsStored, &why).empty());
  EXPECT_EQ(why, "neither PNG nor JPEG data");
  EXPECT_TRUE(decode_image(std::string(), ImageColour::kAsStored, &why).empty());
  EXPECT_EQ(why, "no data");

  std::vector<uint8_t> png = encode_png(picture(64, 48, CV_8UC3));
  for (size_t i = 40; i < png.size(); ++i) png[i] ^= 0x5a;  // header kept, data garbled
  EXPECT_TRUE(decode_image(png, ImageColour::kAsStored, &why).empty());
  EXPECT_NE(why.find("corrupt PNG"), std::string::npos) << why;

  std::vector<uint8_t> jpeg = encode_jpeg(picture(64, 48, CV_8UC3), 90);
  jpeg.resize(20);  // the SOI and a little of the first segment
  EXPECT_TRUE(decode_image(jpeg, ImageColour::kAsStored, &why).empty());
  EXPECT_NE(why.find("corrupt JPEG"), std::string::npos) << why;
}

TEST(ImageCodec, AJpegCutShortDecodesAsFarAsItsDataGoes) {
  const cv::Mat colour = picture(128, 128, CV_8UC3);
  std::vector<uint8_t> jpeg = encode_jpeg(colour, 90);
  jpeg.resize(jpeg.size() * 2 / 3);
  std::string why;
  const cv::Mat back = decode_image(jpeg, ImageColour::kAsStored, &why);
  ASSERT_EQ(back.size(), colour.size());
  EXPECT_NE(why.find("damaged JPEG, decoded as far as it goes: "), std::string::npos) << why;
  // The top rows are there; the rest is what libjpeg fills in.
  EXPECT_GT(psnr(back.rowRange(0, 32), colour.rowRange(0, 32)), 30);
}

TEST(ImageCodec, AHeaderClaimingGiantSizesIsRefusedBeforeAllocating) {
  std::string why;
  std::vector<uint8_t> png = encode_png(picture(16, 16, CV_8UC1));
  // IHDR's width and height (bytes 16-23) say 65535 x 65535, its CRC (bytes 29-32, over
  // bytes 12-28) made to match.
  for (const size_t at : {16, 20}) png[at] = png[at + 1] = 0, put_u16(png, at + 2, 65535);
  const uint32_t crc = static_cast<uint32_t>(crc32(0, png.data() + 12, 17));
  for (int i = 0; i < 4; ++i) png[29 + i] = uint8_t(crc >> (24 - 8 * i));
  EXPECT_TRUE(decode_image(png, ImageColour::kAsStored, &why).empty());
  EXPECT_EQ(why, "PNG of 65535x65535 pixels is too large");

  std::vector<uint8_t> jpeg = encode_jpeg(picture(16, 16, CV_8UC3), 90);
  const size_t sof = marker(jpeg, 0xc0);  // FF C0, length, precision, height, width
  put_u16(jpeg, sof + 5, 60000);             // libjpeg's own limit is 65500 a side
  put_u16(jpeg, sof + 7, 60000);
  EXPECT_TRUE(decode_image(jpeg, ImageColour::kAsStored, &why).empty());
  EXPECT_EQ(why, "JPEG of 60000x60000 pixels is too large");
}

TEST(ImageCodec, ACallerCanAskForASmallerLimit) {
  const std::vector<uint8_t> png = encode_png(picture(40, 30, CV_8UC1));
  std::string why;
  EXPECT_TRUE(decode_image(png, ImageColour::kAsStored, &why, 1199).empty());
  EXPECT_EQ(why, "PNG of 40x30 pixels is too large");
  EXPECT_FALSE(decode_image(png, ImageColour::kAsStored, &why, 1200).empty());
}

TEST(ImageCodec, StrayBytesBetweenJpegMarkersOnlyWarn) {
  // Some cameras pad between segments; libjpeg warns ("extraneous bytes before marker")
  // and decodes, as other readers do.
  const cv::Mat colour = picture(64, 48, CV_8UC3);
  std::vector<uint8_t> jpeg = encode_jpeg(colour, 95);
  const size_t quantisation_table = marker(jpeg, 0xdb);
  jpeg.insert(jpeg.begin() + static_cast<long>(quantisation_table), {0x00, 0x12, 0x34});
  std::string why;
  const cv::Mat back = decode_image(jpeg, ImageColour::kAsStored, &why);
  ASSERT_FALSE(back.empty()) << why;
  EXPECT_GT(psnr(back, colour), 35);
  EXPECT_NE(why.find("extraneous bytes"), std::string::npos) << "the warning is passed on: " << why;
}

TEST(ImageCodec, CmykJpegsAreRefusedByName) {
  const cv::Mat cmyk(16, 16, CV_8UC4, cv::Scalar(10, 20, 30, 40));
  tjhandle tj = tjInitCompress();
  unsigned char* jpeg = nullptr;
  unsigned long size = 0;
  ASSERT_EQ(tjCompress2(tj, cmyk.data, 16, 0, 16, TJPF_CMYK, &jpeg, &size, TJSAMP_444, 90, 0), 0);
  const std::vector<uint8_t> bytes(jpeg, jpeg + size);
  tjFree(jpeg);
  tjDestroy(tj);
  std::string why;
  EXPECT_TRUE(decode_image(bytes, ImageColour::kAsStored, &why).empty());
  EXPECT_EQ(why, "CMYK JPEGs are not supported (save it as RGB)");
}

// The seed files of the decode fuzz target, each a kind of PNG: what they decode to.
TEST(ImageCodec, PngKindsDecodeToEightBitGreyOrBgr) {
  // Colour (x*20, y*25, 100) under alpha x*21: the colour stays, the alpha goes.
  const cv::Mat rgba = read_image(kCorpus + "rgba.png");
  ASSERT_EQ(rgba.type(), CV_8UC3);
  EXPECT_EQ(rgba.at<cv::Vec3b>(4, 7), cv::Vec3b(100, 4 * 25, 7 * 20));
  EXPECT_EQ(rgba.at<cv::Vec3b>(0, 0), cv::Vec3b(100, 0, 0)) << "fully transparent: the colour, not black";
  const cv::Mat grey_alpha = read_image(kCorpus + "grey_alpha.png");
  ASSERT_EQ(grey_alpha.type(), CV_8UC1);
  EXPECT_EQ(grey_alpha.at<uint8_t>(3, 5), 5 * 20);
  // 16-bit grey x*5000+y, scaled to 8 bits.
  const cv::Mat grey16 = read_image(kCorpus + "grey16.png");
  ASSERT_EQ(grey16.type(), CV_8UC1);
  EXPECT_NEAR(grey16.at<uint8_t>(2, 11), (11 * 5000 + 2) / 257.0, 1.0);
  // 1-bit rows: 0x55 (even) or 0xaa (odd), then 0x0f.
  const cv::Mat grey1 = read_image(kCorpus + "grey1.png");
  ASSERT_EQ(grey1.type(), CV_8UC1);
  EXPECT_EQ(grey1.at<uint8_t>(0, 0), 0);
  EXPECT_EQ(grey1.at<uint8_t>(0, 1), 255);
  EXPECT_EQ(grey1.at<uint8_t>(1, 0), 255);
  EXPECT_EQ(grey1.at<uint8_t>(0, 11), 0);
  EXPECT_EQ(grey1.at<uint8_t>(0, 12), 255);
  // 4-bit palette red, green, blue with transparency 255, 128, 0: colours as listed.
  const cv::Mat palette = read_image(kCorpus + "palette.png");
  ASSERT_EQ(palette.type(), CV_8UC3);
  EXPECT_EQ(palette.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 255));  // index 0: red
  EXPECT_EQ(palette.at<cv::Vec3b>(0, 2), cv::Vec3b(0, 255, 0));  // index 1: green
  EXPECT_EQ(palette.at<cv::Vec3b>(2, 3), cv::Vec3b(255, 0, 0));  // index 2: blue, transparent
}

TEST(ImageCodec, OnlyEightBitGreyOrBgrEncodes) {
  EXPECT_THROW(encode_png(cv::Mat()), std::runtime_error);
  EXPECT_THROW(encode_png(cv::Mat(4, 4, CV_16UC1, cv::Scalar(0))), std::runtime_error);
  EXPECT_THROW(encode_jpeg(cv::Mat(4, 4, CV_8UC4, cv::Scalar(0))), std::runtime_error);
}

TEST(ImageFiles, RoundTripByExtension) {
  const testing::TempDir dir;
  const fs::path& dir_ = dir.path();
  const cv::Mat colour = picture(80, 60, CV_8UC3);
  write_image(dir_ / "a.png", colour);
  write_image(dir_ / "b.JPG", colour, 92);
  EXPECT_EQ(max_difference(read_image(dir_ / "a.png"), colour), 0);
  EXPECT_GT(psnr(read_image(dir_ / "b.JPG"), colour), 33);
  EXPECT_EQ(read_image(dir_ / "a.png", ImageColour::kGrey).type(), CV_8UC1);
}

TEST(ImageFiles, ErrorsNameTheFileAndTheReason) {
  const testing::TempDir dir;
  const fs::path& dir_ = dir.path();
  const auto message = [](const auto& call) {
    try {
      call();
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string missing = (dir_ / "missing.png").string();
  EXPECT_EQ(message([&] { read_image(missing); }), "cannot read image '" + missing + "': no such file");
  EXPECT_EQ(message([&] { read_image(dir_); }), "cannot read image '" + dir_.string() + "': it is a folder");
  std::ofstream(dir_ / "text.png") << "hello";
  EXPECT_NE(message([&] { read_image(dir_ / "text.png"); }).find("text.png': not a decodable image"), std::string::npos);
  const std::string tiff = (dir_ / "out.tiff").string();
  EXPECT_EQ(message([&] { write_image(tiff, picture(8, 8, CV_8UC1)); }),
            "cannot write image '" + tiff + "': name it .png, .jpg or .jpeg");
  const std::string nowhere = (dir_ / "no_folder" / "x.png").string();
  EXPECT_EQ(message([&] { write_image(nowhere, picture(8, 8, CV_8UC1)); }),
            "cannot write image '" + nowhere + "': No such file or directory");
}

}  // namespace
}  // namespace omniview
