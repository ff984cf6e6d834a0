// The per-format halves of image_codec.cc (png_codec.cc, jpeg_codec.cc). Decoders return an
// empty Mat and set *error on failure; encoders throw std::runtime_error.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/io/image_codec.h"

namespace omniview::codec_internal {

cv::Mat fail(std::string* error, const std::string& why);
std::string too_large(const char* format, size_t width, size_t height);

cv::Mat decode_png(std::span<const uint8_t> bytes, ImageColour colour, std::string* error, size_t max_pixels);
cv::Mat decode_jpeg(std::span<const uint8_t> bytes, ImageColour colour, std::string* error, size_t max_pixels);
// `image` already checked: CV_8UC1 or CV_8UC3, not empty.
std::vector<uint8_t> encode_png(const cv::Mat& image);
std::vector<uint8_t> encode_jpeg(const cv::Mat& image, int quality);

}  // namespace omniview::codec_internal
