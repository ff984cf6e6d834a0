// Source type `images`: one fixed image per camera, delivered again and again at a rate.
// For demos, tests and views of a still scene.
//
//   - name: still
//     type: images
//     rig: rig.yaml              # our rig YAML or a kalibr camchain
//     rig_frame: base_link       # camchain only: the frame cam0 is placed in
//     rig_pose: [x, y, z, yaw, pitch, roll]   # camchain only: cam0 in rig_frame (m, deg)
//     images: {front: front.jpg, back: back.jpg}   # every rig camera
//
// JPEG and PNG files are also kept as read, so `omniview record` stores them unchanged.
//     rate_hz: 10
#pragma once

#include <memory>
#include <mutex>

#include "server/source/source_registry.h"
#include "server/sources/delivery_thread.h"

namespace omniview {

class ImagesSource : public Source {
 public:
  // Loads and checks the rig and every image; throws ConfigError naming file, line, key.
  explicit ImagesSource(const SourceConfig& config);
  ~ImagesSource() override;

  std::string type() const override { return "images"; }
  std::shared_ptr<const Rig> rig() const override { return rig_; }
  void start(FrameCallback on_frame) override;
  void stop() override;
  SourceHealth health() const override;
  double nominal_rate_hz() const override { return rate_hz_; }

  struct CameraImage {
    cv::Mat image;
    EncodedImage encoded;  // the file's bytes if JPEG or PNG
  };

 private:
  void run(FrameCallback on_frame);

  std::shared_ptr<const Rig> rig_;
  std::vector<cv::Mat> images_;  // never written after construction: shared by every frame set
  std::vector<EncodedImage> encoded_;  // likewise
  double rate_hz_ = 10;
  DeliveryThread thread_;
  mutable std::mutex health_mutex_;
  SourceHealth health_;
};

std::unique_ptr<Source> make_images_source(const SourceConfig& config);

}  // namespace omniview
