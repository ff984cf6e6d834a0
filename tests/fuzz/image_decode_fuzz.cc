// Fuzz target: bytes that arrive as a picture (an image source's files, a recording's
// frames, a robot's JPEG), decoded by core/io/image_codec in each colour mode. An empty
// image is the expected answer to bad input; a crash, a hang, an out-of-bounds access
// (ASan) or any exception is a bug, as is an image that is not 8-bit grey or BGR.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "core/io/image_codec.h"

using namespace omniview;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  for (const ImageColour colour : {ImageColour::kAsStored, ImageColour::kGrey, ImageColour::kBgr}) {
    std::string why;
    // A few bytes may claim a billion pixels; 4 megapixels keep each input quick.
    const cv::Mat image = decode_image(std::span(data, size), colour, &why, size_t(1) << 22);
    if (image.empty()) {
      if (why.empty()) std::abort();  // every refusal says why
      continue;
    }
    if (image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3)) std::abort();
    if (colour == ImageColour::kGrey && image.channels() != 1) std::abort();
    if (colour == ImageColour::kBgr && image.channels() != 3) std::abort();
  }
  return 0;
}
