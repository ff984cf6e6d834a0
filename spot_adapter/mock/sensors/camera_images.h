// The body cameras' pictures: rendered once at start-up (the scene is static; see
// render_pictures), encoded on first request per format and quality, and served from the
// cache after that.
#pragma once

#include <map>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/rig/rig.h"
#include "core/synthetic/scene.h"

namespace omniview::spot_mock {

enum class Encoding { kJpeg, kRaw };

// Renders every camera of `rig` (scene in `world_frame`): CV_8UC3 BGR for a colour robot,
// else CV_8UC1.
std::vector<cv::Mat> render_pictures(const synthetic::Scene& scene, const Rig& rig, const std::string& world_frame,
                                     bool colour, int supersample);

class CameraImages {
 public:
  // One picture per camera: CV_8UC3 BGR for a colour robot, else CV_8UC1.
  CameraImages(std::vector<cv::Mat> pictures, bool colour);

  size_t count() const { return images_.size(); }
  bool colour() const { return colour_; }
  const cv::Mat& image(size_t camera) const { return images_.at(camera); }

  // Camera `camera`'s bytes: JPEG at `quality` (1..100), or raw rows of GREYSCALE_U8 or
  // RGB_U8 (`grey` converts a colour robot's picture). Thread-safe; the reference stays
  // valid for the object's lifetime.
  const std::string& encoded(size_t camera, Encoding encoding, bool grey, int quality);

 private:
  bool colour_;
  std::vector<cv::Mat> images_;
  std::mutex mutex_;
  std::map<std::tuple<size_t, Encoding, bool, int>, std::string> cache_;
};

}  // namespace omniview::spot_mock
