// Dispatch by signature and by file extension, the checks every format shares, and files.
// The formats themselves: png_codec.cc, jpeg_codec.cc.
#include "core/io/image_codec.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "core/io/codecs.h"

namespace omniview {
namespace codec_internal {

cv::Mat fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return {};
}

std::string too_large(const char* format, size_t width, size_t height) {
  return std::string(format) + " of " + std::to_string(width) + "x" + std::to_string(height) + " pixels is too large";
}

}  // namespace codec_internal

namespace {

using codec_internal::fail;

bool is_png(std::span<const uint8_t> b) {
  static constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return b.size() >= 8 && std::equal(kSignature, kSignature + 8, b.begin());
}
bool is_jpeg(std::span<const uint8_t> b) { return b.size() >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff; }

void check_encodable(const cv::Mat& image, const char* format) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw std::runtime_error(std::string("cannot encode ") + format + ": the image must be 8-bit grey or BGR, not " +
                             (image.empty() ? "empty" : "type " + std::to_string(image.type())));
  }
}

std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

std::string image_format(std::span<const uint8_t> bytes) {
  if (is_png(bytes)) return "png";
  if (is_jpeg(bytes)) return "jpeg";
  return "";
}

cv::Mat decode_image(std::span<const uint8_t> bytes, ImageColour colour, std::string* error, size_t max_pixels) {
  if (is_png(bytes)) return codec_internal::decode_png(bytes, colour, error, max_pixels);
  if (is_jpeg(bytes)) return codec_internal::decode_jpeg(bytes, colour, error, max_pixels);
  return fail(error, bytes.empty() ? "no data" : "neither PNG nor JPEG data");
}

cv::Mat decode_image(const std::string& bytes, ImageColour colour, std::string* error, size_t max_pixels) {
  return decode_image(std::span(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()), colour, error,
                      max_pixels);
}

std::vector<uint8_t> encode_png(const cv::Mat& image) {
  check_encodable(image, "PNG");
  return codec_internal::encode_png(image);
}

std::vector<uint8_t> encode_jpeg(const cv::Mat& image, int quality) {
  check_encodable(image, "JPEG");
  if (quality < 1 || quality > 100) throw std::invalid_argument("JPEG quality " + std::to_string(quality) + " is not 1-100");
  return codec_internal::encode_jpeg(image, quality);
}

cv::Mat read_image(const std::filesystem::path& file, ImageColour colour, std::string* why) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return fail(why, "no such file");
  if (std::filesystem::is_directory(file, ec)) return fail(why, "it is a folder");
  std::ifstream in(file, std::ios::binary);
  if (!in) return fail(why, "not readable");
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return fail(why, "not readable");
  std::string error;
  cv::Mat image = decode_image(bytes, colour, &error);
  if (image.empty()) return fail(why, "not a decodable image (" + error + ")");
  if (why && !error.empty()) *why = error;  // decoded, with a warning
  return image;
}

cv::Mat read_image(const std::filesystem::path& file, ImageColour colour) {
  std::string why;
  cv::Mat image = read_image(file, colour, &why);
  if (image.empty()) throw std::runtime_error("cannot read image '" + file.string() + "': " + why);
  return image;
}

const std::vector<std::string>& writable_image_extensions() {
  static const std::vector<std::string> extensions = {".png", ".jpg", ".jpeg"};
  return extensions;
}

void write_image(const std::filesystem::path& file, const cv::Mat& image, int jpeg_quality) {
  const std::string ext = lower_extension(file);
  std::vector<uint8_t> bytes;
  if (ext == ".png") {
    bytes = encode_png(image);
  } else if (ext == ".jpg" || ext == ".jpeg") {
    bytes = encode_jpeg(image, jpeg_quality);
  } else {
    throw std::runtime_error("cannot write image '" + file.string() + "': name it .png, .jpg or .jpeg");
  }
  errno = 0;
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out.flush()) {
    throw std::runtime_error("cannot write image '" + file.string() + "'" +
                             (errno ? std::string(": ") + std::strerror(errno) : std::string()));
  }
}

}  // namespace omniview
