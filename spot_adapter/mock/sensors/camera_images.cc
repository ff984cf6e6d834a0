#include "spot_adapter/mock/sensors/camera_images.h"

#include <opencv2/imgproc.hpp>

#include "core/io/image_codec.h"
#include "core/synthetic/render.h"

namespace omniview::spot_mock {
namespace {

std::string encode(const cv::Mat& picture, Encoding encoding, int quality) {
  if (encoding == Encoding::kJpeg) {
    const std::vector<uint8_t> jpeg = encode_jpeg(picture, quality);
    return std::string(jpeg.begin(), jpeg.end());
  }
  cv::Mat rows = picture;
  if (picture.channels() == 3) cv::cvtColor(picture, rows, cv::COLOR_BGR2RGB);  // Spot's RGB_U8 order
  return std::string(reinterpret_cast<const char*>(rows.data), rows.total() * rows.elemSize());
}

}  // namespace

std::vector<cv::Mat> render_pictures(const synthetic::Scene& scene, const Rig& rig, const std::string& world_frame,
                                     bool colour, int supersample) {
  std::vector<cv::Mat> pictures;
  for (size_t i = 0; i < rig.cameras().size(); ++i) {
    pictures.push_back(synthetic::render_camera(scene, rig, i, world_frame, {.supersample = supersample, .grey = !colour}));
  }
  return pictures;
}

CameraImages::CameraImages(std::vector<cv::Mat> pictures, bool colour)
    : colour_(colour), images_(std::move(pictures)) {}

const std::string& CameraImages::encoded(size_t camera, Encoding encoding, bool grey, int quality) {
  grey = grey || !colour_;
  if (encoding == Encoding::kRaw) quality = 0;  // one raw copy serves every quality
  const auto key = std::make_tuple(camera, encoding, grey, quality);
  std::lock_guard lock(mutex_);
  auto it = cache_.find(key);
  if (it != cache_.end()) return it->second;
  cv::Mat picture = images_.at(camera);
  if (grey && picture.channels() == 3) cv::cvtColor(picture, picture, cv::COLOR_BGR2GRAY);
  return cache_.emplace(key, encode(picture, encoding, quality)).first->second;
}

}  // namespace omniview::spot_mock
