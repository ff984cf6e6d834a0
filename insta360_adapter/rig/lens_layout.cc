#include "insta360_adapter/rig/lens_layout.h"

#include <set>
#include <stdexcept>

#include <opencv2/core.hpp>

namespace omniview::insta360 {

std::vector<LensCrop> side_by_side(const Rig& calibration) {
  std::vector<LensCrop> crops;
  int x = 0;
  for (const Camera& cam : calibration.cameras()) {
    crops.push_back({cam.name, cv::Rect(x, 0, cam.width, cam.height)});
    x += cam.width;
  }
  return crops;
}

void check_crops(const Rig& calibration, const std::vector<LensCrop>& crops, cv::Size frame) {
  if (crops.empty()) throw std::invalid_argument("no lens crops");
  std::set<std::string> seen;
  for (const auto& c : crops) {
    const Camera* cam = calibration.find(c.camera);
    if (!cam) throw std::invalid_argument("the calibration has no camera '" + c.camera + "'");
    if (!seen.insert(c.camera).second) throw std::invalid_argument("camera '" + c.camera + "' is cropped twice");
    if (c.rect.width != cam->width || c.rect.height != cam->height) {
      throw std::invalid_argument("crop of '" + c.camera + "' is " + std::to_string(c.rect.width) + "x" +
                                  std::to_string(c.rect.height) + ", its calibration is for " +
                                  std::to_string(cam->width) + "x" + std::to_string(cam->height));
    }
    if (c.rect.x < 0 || c.rect.y < 0 || c.rect.x + c.rect.width > frame.width ||
        c.rect.y + c.rect.height > frame.height) {
      throw std::invalid_argument("crop of '" + c.camera + "' [" + std::to_string(c.rect.x) + ", " +
                                  std::to_string(c.rect.y) + ", " + std::to_string(c.rect.width) + ", " +
                                  std::to_string(c.rect.height) + "] does not fit the device's " +
                                  std::to_string(frame.width) + "x" + std::to_string(frame.height) + " frame");
    }
  }
}

CameraModel shift_and_scale(const CameraModel& model, cv::Point2d offset, int scale) {
  ModelSpec spec = describe(model);
  // Every model's intrinsics end with fu fv pu pv (kalibr's orders).
  const size_t n = spec.intrinsics.size();
  if (n < 4) throw std::invalid_argument("a camera model without fu fv pu pv");
  spec.intrinsics[n - 2] += offset.x;
  spec.intrinsics[n - 1] += offset.y;
  if (scale != 1) {
    spec.intrinsics[n - 4] /= scale;
    spec.intrinsics[n - 3] /= scale;
    spec.intrinsics[n - 2] = (spec.intrinsics[n - 2] + 0.5) / scale - 0.5;
    spec.intrinsics[n - 1] = (spec.intrinsics[n - 1] + 0.5) / scale - 0.5;
  }
  return make_camera_model(spec, "scaled lens");
}

Rig frame_rig(const Rig& calibration, const std::vector<LensCrop>& crops, cv::Size frame, int scale) {
  check_crops(calibration, crops, frame);
  Rig rig(calibration.default_frame());
  std::set<std::string> cameras;
  for (const Camera& c : calibration.cameras()) cameras.insert(c.name);
  const FrameGraph& graph = calibration.frames();
  for (const std::string& f : graph.frames()) {
    const auto parent = graph.parent_of(f);
    if (parent && !cameras.count(f)) rig.add_frame(f, *parent, graph.lookup(*parent, f));
  }
  const cv::Size scaled((frame.width + scale - 1) / scale, (frame.height + scale - 1) / scale);
  for (const LensCrop& crop : crops) {
    Camera cam = *calibration.find(crop.camera);
    cam.model = shift_and_scale(cam.model, cv::Point2d(crop.rect.x, crop.rect.y), scale);
    // Only the lens' own rectangle (and the calibration's mask inside it) is usable: the
    // other lens' image lies beside it in the same frame.
    cv::Mat mask = cv::Mat::zeros(frame, CV_8UC1);
    if (cam.mask.empty()) {
      mask(crop.rect).setTo(255);
    } else {
      cam.mask.copyTo(mask(crop.rect));
    }
    if (scale != 1) {
      cv::Mat small(scaled, CV_8UC1);
      for (int y = 0; y < scaled.height; ++y) {
        for (int x = 0; x < scaled.width; ++x) small.at<uint8_t>(y, x) = mask.at<uint8_t>(std::min(frame.height - 1, y * scale + scale / 2), std::min(frame.width - 1, x * scale + scale / 2));
      }
      mask = small;
    }
    cam.mask = mask;
    cam.width = scaled.width;
    cam.height = scaled.height;
    rig.add_camera(std::move(cam));
  }
  return rig;
}

}  // namespace omniview::insta360
