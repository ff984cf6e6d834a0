// PNG through libpng: its simplified API to read (it expands palettes, low bit depths and
// 16-bit samples itself), its full API to write with the fast settings the simplified one
// does not offer.
#include <png.h>
#include <zlib.h>

#include <cstring>

#include <opencv2/imgproc.hpp>

#include "core/io/codecs.h"

namespace omniview::codec_internal {
namespace {

// Writes to a growing buffer; libpng reports errors by longjmp, to write_png_rows.
struct PngOutput {
  std::vector<uint8_t>* bytes = nullptr;
  std::string error;
};

void append_png_bytes(png_structp png, png_bytep data, png_size_t size) {
  auto* out = static_cast<PngOutput*>(png_get_io_ptr(png));
  out->bytes->insert(out->bytes->end(), data, data + size);
}

void flush_nothing(png_structp) {}  // the buffer is memory: nothing to flush

void keep_png_error(png_structp png, png_const_charp message) {
  static_cast<PngOutput*>(png_get_error_ptr(png))->error = message;
  png_longjmp(png, 1);
}

// zlib level 1, the SUB filter and run-length matching: on a 2048x1024 colour view 1.5-1.7x
// as fast as OpenCV's PNG at compression 1 (adaptive filters), within 10 % of its size
// (bench/encode_bench.cc); the simplified API's "fast" mode (level 3, no filter) was
// slower and ~1.8x the size.
// Returns the reason on failure, "" on success.
std::string write_png_rows(const cv::Mat& image, PngOutput& out) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &out, keep_png_error, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return "out of memory";
  }
  // No object with a destructor lives in this frame: longjmp would skip it.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return out.error.empty() ? "libpng failed" : out.error;
  }
  png_set_write_fn(png, &out, append_png_bytes, flush_nothing);
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

}  // namespace

// 16-bit samples are taken as sRGB-coded (as other readers do) rather than linear. An image
// with alpha (or a palette with transparency) is read with its alpha channel, which is then
// dropped: the colour under it stays as stored, not blended onto a background.
cv::Mat decode_png(std::span<const uint8_t> bytes, ImageColour colour, std::string* error, size_t max_pixels) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size())) {
    return fail(error, std::string("corrupt PNG: ") + png.message);
  }
  if (double(png.width) * png.height > double(max_pixels)) {
    png_image_free(&png);
    return fail(error, too_large("PNG", png.width, png.height));
  }
  const bool grey = !(png.format & PNG_FORMAT_FLAG_COLOR);
  const bool alpha = png.format & PNG_FORMAT_FLAG_ALPHA;
  png.format = grey ? (alpha ? PNG_FORMAT_GA : PNG_FORMAT_GRAY) : (alpha ? PNG_FORMAT_BGRA : PNG_FORMAT_BGR);
  png.flags |= PNG_IMAGE_FLAG_16BIT_sRGB;
  const int channels = (grey ? 1 : 3) + (alpha ? 1 : 0);
  cv::Mat image(static_cast<int>(png.height), static_cast<int>(png.width), CV_8UC(channels), cv::Scalar::all(0));
  if (!png_image_finish_read(&png, nullptr, image.data, static_cast<png_int_32>(image.step), nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    return fail(error, "corrupt PNG: " + why);
  }
  if (channels == 2) cv::extractChannel(image, image, 0);
  if (channels == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2BGR);
  if (colour == ImageColour::kGrey && image.channels() == 3) cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
  if (colour == ImageColour::kBgr && image.channels() == 1) cv::cvtColor(image, image, cv::COLOR_GRAY2BGR);
  return image;
}

std::vector<uint8_t> encode_png(const cv::Mat& image) {
  std::vector<uint8_t> bytes;
  bytes.reserve(image.total() * image.channels() / 2);
  PngOutput out{&bytes, {}};
  if (const std::string why = write_png_rows(image, out); !why.empty()) {
    throw std::runtime_error("cannot encode PNG: " + why);
  }
  return bytes;
}

}  // namespace omniview::codec_internal
