// PNG and JPEG in memory and on disk, through libpng's and libjpeg-turbo's own APIs.
//
// Why not OpenCV's imgcodecs: Debian builds it with GDAL, GDCM, OpenEXR, TIFF, WebP and
// OpenJPEG, ~120 shared libraries that every program linking it loads at start (~75 ms
// per start in a release build, ~200 ms under ThreadSanitizer), for two formats we use.
// Images are 8-bit, grey (CV_8UC1) or BGR (CV_8UC3) as in the rest of omniview.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace omniview {

enum class ImageColour {
  kAsStored,  // grey stays grey (CV_8UC1), anything with colour becomes BGR (CV_8UC3)
  kGrey,      // always CV_8UC1 (colour converted to luma)
  kBgr,       // always CV_8UC3
};

// As OpenCV's own limit (CV_IO_MAX_IMAGE_PIXELS): a header that claims more is refused
// before anything is allocated for it.
inline constexpr size_t kMaxImagePixels = size_t(1) << 30;

// PNG or JPEG bytes (told apart by their signature) as an 8-bit image: alpha is dropped
// (the colour under it kept), 16-bit samples are scaled to 8, palettes expanded. Returns an
// empty Mat for anything else, for corrupt data and for a header claiming more than
// max_pixels, with the reason in *error when given. Where libjpeg only warns (data cut
// short: the rest of the picture is grey; stray bytes between markers) the image is
// returned, as other readers do, and *error says what was wrong (a caller shows it as a
// warning); otherwise *error is left as it was. CMYK JPEGs are refused.
// "png" or "jpeg" by the bytes' signature, "" for anything else (nothing is decoded).
std::string image_format(std::span<const uint8_t> bytes);

cv::Mat decode_image(std::span<const uint8_t> bytes, ImageColour colour = ImageColour::kAsStored,
                     std::string* error = nullptr, size_t max_pixels = kMaxImagePixels);
cv::Mat decode_image(const std::string& bytes, ImageColour colour = ImageColour::kAsStored,
                     std::string* error = nullptr, size_t max_pixels = kMaxImagePixels);

// `image` is CV_8UC1 (grey) or CV_8UC3 (BGR); anything else throws std::runtime_error.
// PNG: zlib level 1 with the SUB filter (a stream or a cache, not an archive). JPEG: quality 1-100,
// 4:2:0 chroma for colour.
std::vector<uint8_t> encode_png(const cv::Mat& image);
std::vector<uint8_t> encode_jpeg(const cv::Mat& image, int quality = 90);

// Files: read_image throws std::runtime_error naming the file when it is missing,
// unreadable, or not a PNG/JPEG it can decode. The second form returns an empty Mat
// instead and says why in *why: "no such file", "it is a folder", "not readable" or "not a
// decodable image (...)"; for an image returned with a warning, *why is that warning. write_image picks the format by the extension (.png, .jpg,
// .jpeg; any case) and throws naming the file for any other extension or a failed write.
const std::vector<std::string>& writable_image_extensions();  // ".png", ".jpg", ".jpeg"
cv::Mat read_image(const std::filesystem::path& file, ImageColour colour = ImageColour::kAsStored);
cv::Mat read_image(const std::filesystem::path& file, ImageColour colour, std::string* why);
void write_image(const std::filesystem::path& file, const cv::Mat& image, int jpeg_quality = 95);

}  // namespace omniview
