// Fuzz target: bytes a USB camera or a recording hands the insta360/v4l2 sources. They are
// split as an MJPEG stream, each frame is checked and decoded by TurboJPEG (full size and
// at 1/2 DCT scale), and the bytes are also read as a timestamps file. DecodeError and
// std::runtime_error are the expected answers to bad input; a crash, a hang, an
// out-of-bounds read (ASan) or any other exception is a bug. Frames claiming more than 16
// megapixels are not decoded (the source decodes only frames of its stream's size).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "insta360_adapter/decode/jpeg_decoder.h"
#include "insta360_adapter/decode/mjpeg_stream.h"

using namespace omniview::insta360;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static JpegDecoder decoder;
  const auto frames = split_mjpeg(data, size);
  for (const auto& [offset, length] : frames) {
    if (offset + length > size || length == 0) std::abort();
  }
  // The whole input as one frame too (what a UVC buffer is).
  auto candidates = frames;
  candidates.emplace_back(0, size);
  for (const auto& [offset, length] : candidates) {
    const uint8_t* frame = data + offset;
    (void)mjpeg_frame_problem(frame, length);
    try {
      const JpegHeader h = decoder.header(frame, length);
      if (int64_t(h.width) * h.height > (int64_t{16} << 20)) continue;
      for (int scale : {1, 2}) {
        const cv::Mat image = decoder.decode(frame, length, scale);
        if (image.cols != scaled_size(h.width, scale) || image.rows != scaled_size(h.height, scale)) std::abort();
      }
    } catch (const DecodeError&) {
    }
  }
  try {
    (void)parse_timestamps(std::string(reinterpret_cast<const char*>(data), size), "fuzz");
  } catch (const std::runtime_error&) {
  }
  return 0;
}
