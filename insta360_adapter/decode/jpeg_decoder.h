// MJPEG frames -> BGR images with libjpeg-turbo's TurboJPEG API, decoded straight into the
// packed BGR rows the fusion maps read (no colour swap or copy afterwards), optionally at
// 1/2, 1/4 or 1/8 size by DCT scaling (the decoder skips the high frequencies instead of
// decoding everything and shrinking it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <opencv2/core/mat.hpp>

namespace omniview::insta360 {

class DecodeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct JpegHeader {
  int width = 0, height = 0;
};

class JpegDecoder {
 public:
  JpegDecoder();
  ~JpegDecoder();
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;

  // Throws DecodeError for data that is no JPEG (or a truncated header).
  JpegHeader header(const uint8_t* data, size_t size);
  // A new CV_8UC3 BGR image of ceil(width / scale) x ceil(height / scale); scale is 1, 2,
  // 4 or 8. Throws DecodeError for corrupt data, including what libjpeg only warns about
  // (a truncated frame decodes with a grey bottom: better skipped than shown).
  cv::Mat decode(const uint8_t* data, size_t size, int scale = 1);
  // The same into `out` (allocated if its size or type differs).
  void decode_into(const uint8_t* data, size_t size, int scale, cv::Mat& out);

 private:
  void* handle_;
};

// Size of an image decoded at 1/scale (TurboJPEG rounds up).
inline int scaled_size(int size, int scale) { return (size + scale - 1) / scale; }

}  // namespace omniview::insta360
