#include "server/pipeline/frame_encoder.h"

#include <stdexcept>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace omniview {

EncodingKey encoding_key(v1::Encoding encoding, int quality, bool gray) {
  EncodingKey key;
  key.gray = gray;
  switch (encoding) {
    case v1::ENCODING_UNSPECIFIED:
    case v1::JPEG:
      key.encoding = v1::JPEG;
      if (quality == 0) quality = 85;
      if (quality < 1 || quality > 100) {
        throw std::invalid_argument("quality must be 1..100 for JPEG (0 for the default 85), got " +
                                    std::to_string(quality));
      }
      key.quality = quality;
      return key;
    case v1::PNG:
    case v1::RAW:
      key.encoding = encoding;
      key.quality = 0;  // lossless: quality has no meaning, and must not split the groups
      return key;
    default:
      throw std::invalid_argument("unknown encoding " + std::to_string(encoding) + " (JPEG, PNG or RAW)");
  }
}

std::string to_string(const EncodingKey& key) {
  std::string s = key.encoding == v1::PNG ? "png" : key.encoding == v1::RAW ? "raw" : "jpeg";
  if (key.encoding == v1::JPEG) s += " q" + std::to_string(key.quality);
  if (key.gray) s += " gray";
  return s;
}

void encode_frame(const cv::Mat& image, const EncodingKey& key, v1::Frame& frame) {
  cv::Mat pixels = image;
  if (key.gray && image.channels() == 3) cv::cvtColor(image, pixels, cv::COLOR_BGR2GRAY);
  frame.set_encoding(key.encoding);
  frame.set_width(pixels.cols);
  frame.set_height(pixels.rows);
  frame.set_channels(pixels.channels());
  if (key.encoding == v1::RAW) {
    cv::Mat rgb = pixels;
    if (pixels.channels() == 3) cv::cvtColor(pixels, rgb, cv::COLOR_BGR2RGB);
    if (!rgb.isContinuous()) rgb = rgb.clone();
    frame.set_data(rgb.data, rgb.total() * rgb.elemSize());
    return;
  }
  std::vector<uint8_t> bytes;
  std::vector<int> params;
  const char* ext = ".png";
  if (key.encoding == v1::JPEG) {
    ext = ".jpg";
    params = {cv::IMWRITE_JPEG_QUALITY, key.quality};
  } else {
    params = {cv::IMWRITE_PNG_COMPRESSION, 1};  // fast: a stream is no archive
  }
  if (!cv::imencode(ext, pixels, bytes, params)) throw std::runtime_error(std::string("cannot encode ") + ext);
  frame.set_data(bytes.data(), bytes.size());
}

}  // namespace omniview
