#include "insta360_adapter/decode/jpeg_decoder.h"

#include <turbojpeg.h>

namespace omniview::insta360 {

JpegDecoder::JpegDecoder() : handle_(tjInitDecompress()) {
  if (!handle_) throw std::runtime_error(std::string("TurboJPEG: cannot start a decoder: ") + tjGetErrorStr2(nullptr));
}

JpegDecoder::~JpegDecoder() { tjDestroy(handle_); }

JpegHeader JpegDecoder::header(const uint8_t* data, size_t size) {
  if (size < 4 || data[0] != 0xFF || data[1] != 0xD8) throw DecodeError("not a JPEG (no start-of-image marker)");
  int w = 0, h = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(handle_, data, static_cast<unsigned long>(size), &w, &h, &subsampling, &colorspace) != 0) {
    throw DecodeError(std::string("bad JPEG header: ") + tjGetErrorStr2(handle_));
  }
  if (w <= 0 || h <= 0) throw DecodeError("JPEG of size 0");
  return {w, h};
}

cv::Mat JpegDecoder::decode(const uint8_t* data, size_t size, int scale) {
  cv::Mat out;
  decode_into(data, size, scale, out);
  return out;
}

void JpegDecoder::decode_into(const uint8_t* data, size_t size, int scale, cv::Mat& out) {
  if (scale != 1 && scale != 2 && scale != 4 && scale != 8) throw std::invalid_argument("JPEG scale must be 1, 2, 4 or 8");
  const JpegHeader h = header(data, size);
  const int w = scaled_size(h.width, scale), ht = scaled_size(h.height, scale);
  out.create(ht, w, CV_8UC3);
  // STOPONWARNING: a truncated or damaged frame fails instead of decoding half grey.
  if (tjDecompress2(handle_, data, static_cast<unsigned long>(size), out.data, w, static_cast<int>(out.step[0]), ht,
                    TJPF_BGR, TJFLAG_STOPONWARNING) != 0) {
    throw DecodeError(std::string("corrupt JPEG: ") + tjGetErrorStr2(handle_));
  }
}

}  // namespace omniview::insta360
