// JPEG through libjpeg-turbo: libjpeg's own API to read, whose error manager tells a fatal
// error (no image) from a warning (data cut short, stray bytes between markers: the image
// stands, as other readers give it); TurboJPEG's API to write.
#include <csetjmp>
#include <cstdio>  // jpeglib.h uses FILE

#include <jpeglib.h>
#include <turbojpeg.h>

#include <memory>

#include "core/io/codecs.h"

namespace omniview::codec_internal {
namespace {

// libjpeg calls error_exit for a fatal error and must not return from it: it longjmps back
// to the phase (read_header, read_pixels) that set `jump`. Warnings are not printed; the
// first is kept for the caller.
struct JpegErrors {
  jpeg_error_mgr base;  // first: libjpeg hands error_exit a pointer to it
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {};
  char first_warning[JMSG_LENGTH_MAX] = {};
};

void on_fatal_error(j_common_ptr info) {
  auto* errors = reinterpret_cast<JpegErrors*>(info->err);
  info->err->format_message(info, errors->message);
  std::longjmp(errors->jump, 1);
}

void on_message(j_common_ptr info, int level) {
  if (level >= 0) return;  // trace messages
  if (info->err->num_warnings++ == 0) {
    info->err->format_message(info, reinterpret_cast<JpegErrors*>(info->err)->first_warning);
  }
}

struct JpegReader {
  JpegReader() {
    info.err = jpeg_std_error(&errors.base);
    errors.base.error_exit = on_fatal_error;
    errors.base.emit_message = on_message;
  }
  ~JpegReader() {
    if (created) jpeg_destroy_decompress(&info);
  }
  JpegReader(const JpegReader&) = delete;
  JpegReader& operator=(const JpegReader&) = delete;

  jpeg_decompress_struct info{};
  JpegErrors errors;
  bool created = false;
};

// Each phase returns the fatal error's message, or nullptr. No object with a destructor
// lives in their frames: longjmp would skip it.
const char* read_header(JpegReader& r, std::span<const uint8_t> bytes) {
  if (setjmp(r.errors.jump)) return r.errors.message;
  jpeg_create_decompress(&r.info);
  r.created = true;
  jpeg_mem_src(&r.info, bytes.data(), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&r.info, TRUE);
  return nullptr;
}

const char* read_pixels(JpegReader& r, cv::Mat& image) {
  if (setjmp(r.errors.jump)) return r.errors.message;
  jpeg_start_decompress(&r.info);
  while (r.info.output_scanline < r.info.output_height) {
    JSAMPROW row = image.ptr(static_cast<int>(r.info.output_scanline));
    jpeg_read_scanlines(&r.info, &row, 1);
  }
  jpeg_finish_decompress(&r.info);
  return nullptr;
}

struct TurboJpegHandle {
  void operator()(void* handle) const { tjDestroy(handle); }
};

}  // namespace

cv::Mat decode_jpeg(std::span<const uint8_t> bytes, ImageColour colour, std::string* error, size_t max_pixels) {
  JpegReader reader;
  if (const char* why = read_header(reader, bytes)) return fail(error, std::string("corrupt JPEG: ") + why);
  const jpeg_decompress_struct& info = reader.info;
  if (double(info.image_width) * info.image_height > double(max_pixels)) {
    return fail(error, too_large("JPEG", info.image_width, info.image_height));
  }
  if (info.jpeg_color_space == JCS_CMYK || info.jpeg_color_space == JCS_YCCK) {
    return fail(error, "CMYK JPEGs are not supported (save it as RGB)");
  }
  const bool grey =
      colour == ImageColour::kGrey || (colour == ImageColour::kAsStored && info.jpeg_color_space == JCS_GRAYSCALE);
  reader.info.out_color_space = grey ? JCS_GRAYSCALE : JCS_EXT_BGR;
  cv::Mat image(static_cast<int>(info.image_height), static_cast<int>(info.image_width), grey ? CV_8UC1 : CV_8UC3);
  if (const char* why = read_pixels(reader, image)) return fail(error, std::string("corrupt JPEG: ") + why);
  if (reader.errors.base.num_warnings > 0 && error) {
    *error = std::string("damaged JPEG, decoded as far as it goes: ") + reader.errors.first_warning;
  }
  return image;
}

// The accurate DCT, as libjpeg's default (TurboJPEG's own default when compressing is the
// fast one, a little blurrier at the same quality).
std::vector<uint8_t> encode_jpeg(const cv::Mat& image, int quality) {
  const std::unique_ptr<void, TurboJpegHandle> tj(tjInitCompress());
  if (!tj) throw std::runtime_error("cannot start a JPEG encoder");
  const bool grey = image.channels() == 1;
  unsigned char* jpeg = nullptr;
  unsigned long size = 0;
  if (tjCompress2(tj.get(), image.data, image.cols, static_cast<int>(image.step), image.rows, grey ? TJPF_GRAY : TJPF_BGR,
                  &jpeg, &size, grey ? TJSAMP_GRAY : TJSAMP_420, quality, TJFLAG_ACCURATEDCT) != 0) {
    tjFree(jpeg);
    throw std::runtime_error(std::string("cannot encode JPEG: ") + tjGetErrorStr2(tj.get()));
  }
  std::vector<uint8_t> out(jpeg, jpeg + size);
  tjFree(jpeg);
  return out;
}

}  // namespace omniview::codec_internal
