#include "core/io/image_codec.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>

#include <png.h>
#include <turbojpeg.h>
#include <zlib.h>

#include <opencv2/imgproc.hpp>

namespace omniview {
namespace {

bool is_png(std::span<const uint8_t> b) {
  static constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return b.size() >= 8 && std::equal(kSignature, kSignature + 8, b.begin());
}
bool is_jpeg(std::span<const uint8_t> b) { return b.size() >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff; }

// As OpenCV's own limit (CV_IO_MAX_IMAGE_PIXELS): a header that claims more is refused
// before anything is allocated for it.
constexpr double kMaxPixels = double(1 << 30);

cv::Mat fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return {};
}

cv::Mat to_colour(cv::Mat image, ImageColour colour) {
  if (colour == ImageColour::kGrey && image.channels() == 3) cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
  if (colour == ImageColour::kBgr && image.channels() == 1) cv::cvtColor(image, image, cv::COLOR_GRAY2BGR);
  return image;
}

// libpng's simplified API: it expands palettes and low bit depths itself; 16-bit samples
// are taken as sRGB-coded (as other readers do) rather than linear, and alpha is dropped
// by composing on black.
cv::Mat decode_png(std::span<const uint8_t> bytes, ImageColour colour, std::string* error) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size())) {
    return fail(error, std::string("corrupt PNG: ") + png.message);
  }
  if (double(png.width) * png.height > kMaxPixels) {
    png_image_free(&png);
    return fail(error, "PNG of " + std::to_string(png.width) + "x" + std::to_string(png.height) + " pixels is too large");
  }
  const bool grey = !(png.format & PNG_FORMAT_FLAG_COLOR);
  png.format = grey ? PNG_FORMAT_GRAY : PNG_FORMAT_BGR;
  png.flags |= PNG_IMAGE_FLAG_16BIT_sRGB;
  cv::Mat image(static_cast<int>(png.height), static_cast<int>(png.width), grey ? CV_8UC1 : CV_8UC3, cv::Scalar::all(0));
  if (!png_image_finish_read(&png, nullptr, image.data, static_cast<png_int_32>(image.step), nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    return fail(error, "corrupt PNG: " + why);
  }
  return to_colour(image, colour);
}

struct TurboJpegHandle {
  void operator()(void* handle) const { tjDestroy(handle); }
};
using TurboJpeg = std::unique_ptr<void, TurboJpegHandle>;

cv::Mat decode_jpeg(std::span<const uint8_t> bytes, ImageColour colour, std::string* error) {
  const TurboJpeg tj(tjInitDecompress());
  if (!tj) return fail(error, "cannot start a JPEG decoder");
  int width = 0, height = 0, subsampling = 0, colourspace = 0;
  if (tjDecompressHeader3(tj.get(), bytes.data(), bytes.size(), &width, &height, &subsampling, &colourspace) != 0) {
    return fail(error, std::string("corrupt JPEG: ") + tjGetErrorStr2(tj.get()));
  }
  if (double(width) * height > kMaxPixels) {
    return fail(error, "JPEG of " + std::to_string(width) + "x" + std::to_string(height) + " pixels is too large");
  }
  const bool grey = colour == ImageColour::kGrey || (colour == ImageColour::kAsStored && colourspace == TJCS_GRAY);
  cv::Mat image(height, width, grey ? CV_8UC1 : CV_8UC3);
  // A warning (data cut short, bytes before a marker) still leaves a picture, as libjpeg
  // leaves it; only a fatal error fails.
  if (tjDecompress2(tj.get(), bytes.data(), bytes.size(), image.data, width, static_cast<int>(image.step), height,
                    grey ? TJPF_GRAY : TJPF_BGR, 0) != 0 &&
      tjGetErrorCode(tj.get()) != TJERR_WARNING) {
    return fail(error, std::string("corrupt JPEG: ") + tjGetErrorStr2(tj.get()));
  }
  return image;
}

// libpng's full write API, for the settings its simplified one does not offer: zlib level
// 1, the SUB filter and run-length matching. On a 2048x1024 colour view that is ~1.7x as
// fast as OpenCV's PNG at compression 1 (adaptive filters) and a little smaller; the
// simplified API's "fast" mode (level 3, no filter) was slower and ~1.8x the size.
// Returns the reason on failure (libpng reports errors by longjmp, caught here).
void append_png_bytes(png_structp png, png_bytep data, png_size_t size) {
  auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + size);
}

void keep_png_error(png_structp png, png_const_charp message) {
  *static_cast<std::string*>(png_get_error_ptr(png)) = message;
  png_longjmp(png, 1);
}

std::string write_png_rows(const cv::Mat& image, std::vector<uint8_t>& out) {
  std::string error;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, keep_png_error, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return "out of memory";
  }
  // Nothing with a destructor lives in this frame past here: longjmp skips destructors.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return error.empty() ? "libpng failed" : error;
  }
  png_set_write_fn(png, &out, append_png_bytes, nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows), 8,
               image.channels() == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 1);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_strategy(png, Z_RLE);
  png_write_info(png, info);
  if (image.channels() == 3) png_set_bgr(png);
  for (int v = 0; v < image.rows; ++v) png_write_row(png, image.ptr(v));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return {};
}

void check_encodable(const cv::Mat& image, const char* format) {
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) {
    throw std::invalid_argument(std::string("cannot encode ") + format + ": the image must be 8-bit grey or BGR, not " +
                                (image.empty() ? "empty" : "type " + std::to_string(image.type())));
  }
}

std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

cv::Mat decode_image(std::span<const uint8_t> bytes, ImageColour colour, std::string* error) {
  if (is_png(bytes)) return decode_png(bytes, colour, error);
  if (is_jpeg(bytes)) return decode_jpeg(bytes, colour, error);
  return fail(error, bytes.empty() ? "no data" : "neither PNG nor JPEG data");
}

cv::Mat decode_image(const std::string& bytes, ImageColour colour, std::string* error) {
  return decode_image(std::span(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()), colour, error);
}

std::vector<uint8_t> encode_png(const cv::Mat& image) {
  check_encodable(image, "PNG");
  std::vector<uint8_t> out;
  out.reserve(image.total() * image.channels() / 2);
  if (const std::string why = write_png_rows(image, out); !why.empty()) {
    throw std::runtime_error("cannot encode PNG: " + why);
  }
  return out;
}

std::vector<uint8_t> encode_jpeg(const cv::Mat& image, int quality) {
  check_encodable(image, "JPEG");
  if (quality < 1 || quality > 100) throw std::invalid_argument("JPEG quality " + std::to_string(quality) + " is not 1-100");
  const TurboJpeg tj(tjInitCompress());
  if (!tj) throw std::runtime_error("cannot start a JPEG encoder");
  const bool grey = image.channels() == 1;
  unsigned char* jpeg = nullptr;
  unsigned long size = 0;
  if (tjCompress2(tj.get(), image.data, image.cols, static_cast<int>(image.step), image.rows, grey ? TJPF_GRAY : TJPF_BGR,
                  &jpeg, &size, grey ? TJSAMP_GRAY : TJSAMP_420, quality, 0) != 0) {
    tjFree(jpeg);
    throw std::runtime_error(std::string("cannot encode JPEG: ") + tjGetErrorStr2(tj.get()));
  }
  std::vector<uint8_t> out(jpeg, jpeg + size);
  tjFree(jpeg);
  return out;
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
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out.flush()) throw std::runtime_error("cannot write image '" + file.string() + "'");
}

}  // namespace omniview
