#include "server/pipeline/frame_encoder.h"

#include <stdexcept>
#include <vector>

#include <opencv2/imgproc.hpp>
#include <turbojpeg.h>

#include "core/io/image_codec.h"
#include "server/pipeline/video_stream.h"
#include "server/video/h264_encoder.h"

namespace omniview {
namespace {

// One TurboJPEG compressor and output buffer per encoder thread, reused frame after frame;
// the buffer has TurboJPEG's worst-case size for the frame, so it never reallocates.
struct JpegCompressor {
  tjhandle handle = tjInitCompress();
  unsigned char* buffer = nullptr;
  unsigned long capacity = 0;
  ~JpegCompressor() {
    tjFree(buffer);
    if (handle != nullptr) tjDestroy(handle);
  }
};

// JPEG straight from the view's buffer: BGR or grey as it lies in memory, rows at the Mat's
// own stride, no swap and no copy. A grey key over a colour view keeps only the luma
// (TJSAMP_GRAY), which is what converting to grey first would give.
void encode_jpeg(const cv::Mat& image, int quality, bool gray, v1::Frame& frame) {
  thread_local JpegCompressor jpeg;
  if (jpeg.handle == nullptr) throw std::runtime_error("cannot start the JPEG encoder (TurboJPEG)");
  const bool colour = image.channels() == 3;
  const int format = colour ? TJPF_BGR : TJPF_GRAY;
  const int subsampling = gray || !colour ? TJSAMP_GRAY : TJSAMP_420;
  const unsigned long needed = tjBufSize(image.cols, image.rows, subsampling);
  if (jpeg.capacity < needed) {
    tjFree(jpeg.buffer);
    jpeg.buffer = tjAlloc(static_cast<int>(needed));
    jpeg.capacity = jpeg.buffer != nullptr ? needed : 0;
    if (jpeg.buffer == nullptr) throw std::runtime_error("cannot encode JPEG: out of memory");
  }
  unsigned long size = jpeg.capacity;
  if (tjCompress2(jpeg.handle, image.data, image.cols, static_cast<int>(image.step[0]), image.rows, format, &jpeg.buffer,
                  &size, subsampling, quality, TJFLAG_NOREALLOC) != 0) {
    throw std::runtime_error(std::string("cannot encode JPEG: ") + tjGetErrorStr2(jpeg.handle));
  }
  frame.set_channels(subsampling == TJSAMP_GRAY ? 1 : 3);
  frame.set_data(jpeg.buffer, size);
}

}  // namespace

EncodingKey encoding_key(v1::Encoding encoding, int quality, bool gray, int max_kbps) {
  EncodingKey key;
  key.gray = gray;
  if (max_kbps != 0 && encoding != v1::H264) {
    throw std::invalid_argument("max_bitrate_kbps applies to H264 streams only (got " + std::to_string(max_kbps) +
                                " kbit/s for " + v1::Encoding_Name(encoding) + ")");
  }
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
    case v1::H264:
      key.encoding = v1::H264;
      if (quality < 0 || quality > 100) {
        throw std::invalid_argument("quality must be 1..100 for H264 (CRF = 51 - quality/2; 0 for the default " +
                                    std::to_string(kDefaultH264Quality) + ", CRF 26), got " + std::to_string(quality));
      }
      if (max_kbps != 0 && (max_kbps < video::kMinKbps || max_kbps > video::kMaxKbps)) {
        throw std::invalid_argument("max_bitrate_kbps must be " + std::to_string(video::kMinKbps) + ".." +
                                    std::to_string(video::kMaxKbps) + " (0: no ceiling), got " +
                                    std::to_string(max_kbps));
      }
      key.quality = quality == 0 ? kDefaultH264Quality : quality;
      key.max_kbps = max_kbps;
      return key;
    default:
      throw std::invalid_argument("unknown encoding " + std::to_string(encoding) + " (JPEG, PNG, RAW or H264)");
  }
}

std::string to_string(const EncodingKey& key) {
  std::string s = key.encoding == v1::PNG    ? "png"
                  : key.encoding == v1::RAW  ? "raw"
                  : key.encoding == v1::H264 ? "h264"
                                             : "jpeg";
  if (key.encoding == v1::JPEG || key.encoding == v1::H264) s += " q" + std::to_string(key.quality);
  if (key.max_kbps > 0) s += " <=" + std::to_string(key.max_kbps) + "kbit/s";
  if (key.gray) s += " gray";
  return s;
}

void encode_frame(const cv::Mat& image, const EncodingKey& key, v1::Frame& frame) {
  if (image.type() != CV_8UC1 && image.type() != CV_8UC3) {
    throw std::runtime_error("cannot encode an image of OpenCV type " + std::to_string(image.type()));
  }
  if (key.encoding == v1::H264) throw std::logic_error("H.264 frames are encoded by their group's VideoStream");
  frame.set_encoding(key.encoding);
  frame.set_key_frame(true);  // every still is
  frame.set_width(image.cols);
  frame.set_height(image.rows);
  if (key.encoding == v1::JPEG) return encode_jpeg(image, key.quality, key.gray, frame);
  cv::Mat pixels = image;
  if (key.gray && image.channels() == 3) cv::cvtColor(image, pixels, cv::COLOR_BGR2GRAY);
  frame.set_channels(pixels.channels());
  if (key.encoding == v1::RAW) {
    cv::Mat rgb = pixels;
    if (pixels.channels() == 3) cv::cvtColor(pixels, rgb, cv::COLOR_BGR2RGB);
    if (!rgb.isContinuous()) rgb = rgb.clone();
    frame.set_data(rgb.data, rgb.total() * rgb.elemSize());
    return;
  }
  const std::vector<uint8_t> bytes = encode_png(pixels);  // fast settings: a stream is no archive
  frame.set_data(bytes.data(), bytes.size());
}

}  // namespace omniview
