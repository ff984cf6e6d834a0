// A real H.264 decoder for the tests (libavcodec, linked by the tests only): access units
// in, I420 pictures out, and every error it reports counted.
#pragma once

#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>

namespace omniview::testing {

class H264Decoder {
 public:
  H264Decoder();
  ~H264Decoder();
  H264Decoder(const H264Decoder&) = delete;
  H264Decoder& operator=(const H264Decoder&) = delete;

  // Decodes one Annex-B access unit. Returns the picture it completes as I420 (height * 3/2
  // rows of `width` bytes: Y, then U, then V), or an empty Mat where the decoder gave none
  // or failed (errors() counts the failures, last_error() says why).
  cv::Mat decode(const std::string& access_unit);
  // The picture's luma plane, a view into an I420 Mat from decode().
  static cv::Mat luma(const cv::Mat& i420, int width, int height);

  int errors() const { return errors_; }
  // The decoder concealed damage in a picture (a missing reference): also counted in errors().
  int corrupt_pictures() const { return corrupt_; }
  const std::string& last_error() const { return last_error_; }
  bool full_range() const { return full_range_; }

 private:
  struct Av;
  std::unique_ptr<Av> av_;
  int errors_ = 0;
  int corrupt_ = 0;
  bool full_range_ = false;
  std::string last_error_;
};

// PSNR of two 8-bit single-channel images of one size (infinity where equal).
double psnr(const cv::Mat& a, const cv::Mat& b);

}  // namespace omniview::testing
