#include "spot_adapter/convert/image_from_response.h"

#include <opencv2/imgproc.hpp>

#include "core/io/image_codec.h"
#include "spot_adapter/client/spot_error.h"

namespace omniview::spot {
namespace {

namespace api = bosdyn::api;

[[noreturn]] void fail(const std::string& camera, const std::string& message) {
  throw SpotError(SpotError::Kind::kProtocol, "camera '" + camera + "': " + message);
}

std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

cv::Mat decode_raw(const api::Image& img, const std::string& camera) {
  const auto& data = img.data();
  // cols x rows comes from the wire: check it against the data before trusting it.
  const auto pixels = static_cast<size_t>(img.cols()) * static_cast<size_t>(img.rows());
  int type = 0, channels = 0;
  switch (img.pixel_format()) {
    case api::Image::PIXEL_FORMAT_GREYSCALE_U8: type = CV_8UC1, channels = 1; break;
    case api::Image::PIXEL_FORMAT_RGB_U8: type = CV_8UC3, channels = 3; break;
    case api::Image::PIXEL_FORMAT_RGBA_U8: type = CV_8UC4, channels = 4; break;
    default:
      fail(camera, "RAW pixel format " + api::Image::PixelFormat_Name(img.pixel_format()) +
                       " is not a visual image (request greyscale or RGB)");
  }
  if (data.size() != pixels * static_cast<size_t>(channels)) {
    fail(camera, "RAW image says " + size_text(img.cols(), img.rows()) + " with " + std::to_string(channels) +
                     " channel(s) but carries " + std::to_string(data.size()) + " bytes");
  }
  const cv::Mat wrapped(img.rows(), img.cols(), type, const_cast<char*>(data.data()));
  cv::Mat out;
  if (channels == 1) out = wrapped.clone();
  else cv::cvtColor(wrapped, out, channels == 3 ? cv::COLOR_RGB2BGR : cv::COLOR_RGBA2BGR);
  return out;
}

// Width and height from a JPEG's frame header, read before decoding: the header, not the
// response, decides how much memory the decoder takes. False when there is none.
bool jpeg_size(const std::string& data, int& width, int& height) {
  const auto byte = [&](size_t i) { return static_cast<unsigned>(static_cast<unsigned char>(data[i])); };
  if (data.size() < 4 || byte(0) != 0xFF || byte(1) != 0xD8) return false;
  size_t i = 2;
  while (i + 4 <= data.size()) {
    if (byte(i) != 0xFF) return false;
    const unsigned marker = byte(i + 1);
    if (marker == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    const size_t length = (byte(i + 2) << 8) | byte(i + 3);
    const bool frame_header = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame_header) {
      if (i + 9 > data.size()) return false;
      height = static_cast<int>((byte(i + 5) << 8) | byte(i + 6));
      width = static_cast<int>((byte(i + 7) << 8) | byte(i + 8));
      return true;
    }
    if (length < 2) return false;
    i += 2 + length;
  }
  return false;
}

}  // namespace

DecodedImage decode_image_response(const api::ImageResponse& response, const std::string& camera, int width,
                                   int height) {
  if (response.status() != api::ImageResponse::STATUS_OK) {
    fail(camera, "the robot answered " + api::ImageResponse::Status_Name(response.status()));
  }
  const api::Image& img = response.shot().image();
  if (img.cols() != width || img.rows() != height) {
    fail(camera, "image is " + size_text(img.cols(), img.rows()) + ", the camera is calibrated for " +
                     size_text(width, height));
  }
  if (img.data().empty()) fail(camera, "the image carries no data");
  DecodedImage out;
  switch (img.format()) {
    case api::Image::FORMAT_JPEG: {
      int w = 0, h = 0;
      if (!jpeg_size(img.data(), w, h)) fail(camera, "corrupt JPEG: no frame header");
      if (w != width || h != height) {
        fail(camera, "JPEG is " + size_text(w, h) + " but the response says " + size_text(img.cols(), img.rows()));
      }
      std::string why;
      out.image = decode_image(img.data(), ImageColour::kAsStored, &why);
      // A JPEG that decoded only in part (libjpeg's warning: truncated, a bad Huffman code)
      // is as much an error as one that did not decode: its rest would be a flat grey patch
      // shown as live picture. The camera's last whole image stands in for it.
      const std::string bytes = " (" + std::to_string(img.data().size()) + " bytes)";
      if (out.image.empty()) fail(camera, why + bytes);
      if (!why.empty()) fail(camera, "damaged JPEG: " + why.substr(why.find(": ") + 2) + bytes);
      if (out.image.cols != width || out.image.rows != height) {
        fail(camera, "JPEG decodes to " + size_text(out.image.cols, out.image.rows) + " but the response says " +
                         size_text(img.cols(), img.rows()));
      }
      out.encoded.format = "jpeg";
      out.encoded.bytes = std::make_shared<const std::vector<uint8_t>>(img.data().begin(), img.data().end());
      break;
    }
    case api::Image::FORMAT_RAW:
      out.image = decode_raw(img, camera);
      break;
    default:
      fail(camera, "image format " + api::Image::Format_Name(img.format()) + " is not supported (request JPEG or RAW)");
  }
  return out;
}

}  // namespace omniview::spot
