#include "server/sources/images_source.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>

#include "core/io/image_codec.h"
#include "server/sources/source_config_helpers.h"

namespace omniview {
namespace {

// Decodes a camera's image file (JPEG or PNG) and keeps its bytes, so that a recording of
// this source stores the file as it is (no re-encoding, no loss).
ImagesSource::CameraImage load_camera_image(const SourceConfig& config, const YAML::Node& node, const std::string& key,
                                            const Camera& cam) {
  const YamlReader& r = *config.reader;
  std::string path = r.text(node, key);
  if (!std::filesystem::path(path).is_absolute() && !config.folder.empty()) {
    path = (std::filesystem::path(config.folder) / path).string();
  }
  std::ifstream in(path, std::ios::binary);
  auto bytes = std::make_shared<std::vector<uint8_t>>();
  if (in) bytes->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  // Grey stays grey, colour becomes BGR, as a replay of a recording will decode it.
  std::string why;
  cv::Mat image = bytes->empty() ? cv::Mat() : decode_image(*bytes, ImageColour::kAsStored, &why);
  if (image.empty()) {
    r.fail(node, key, "cannot read image '" + path + "' for camera '" + cam.name +
                          "': " + (bytes->empty() ? "missing, unreadable or empty" : why));
  }
  if (!why.empty()) {  // decoded, but damaged: served as it is, and said once
    std::cerr << "omniviewd: image '" << path << "' for camera '" << cam.name << "': " << why << "\n";
  }
  if (image.cols != cam.width || image.rows != cam.height) {
    r.fail(node, key, "image '" + path + "' is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                          ", camera '" + cam.name + "' is calibrated for " + std::to_string(cam.width) + "x" +
                          std::to_string(cam.height));
  }
  EncodedImage encoded;
  encoded.format = image_format(*bytes);
  encoded.bytes = std::move(bytes);
  return {std::move(image), std::move(encoded)};
}

}  // namespace

ImagesSource::ImagesSource(const SourceConfig& config) : Source(config.name) {
  const YamlReader& r = *config.reader;
  r.expect_keys(config.node, config.path, {"name", "type", "rig", "rig_frame", "rig_pose", "images", "rate_hz"});
  rig_ = load_config_rig(config);
  rate_hz_ = positive_number(config, "rate_hz", 10);
  const std::string images_key = config.path + ".images";
  const YAML::Node images = r.required(config.node, "images", config.path);
  if (!images.IsMap()) r.fail(images, images_key, "expected a map {camera: image file}");
  for (const auto& kv : images) {
    const std::string camera = kv.first.Scalar();
    if (!rig_->find(camera)) r.fail(kv.first, images_key + "." + camera, "the rig has no camera '" + camera + "'");
  }
  for (const Camera& cam : rig_->cameras()) {
    const YAML::Node node = images[cam.name];
    if (!node) r.fail(images, images_key, "no image for camera '" + cam.name + "' (every rig camera needs one)");
    CameraImage loaded = load_camera_image(config, node, images_key + "." + cam.name, cam);
    images_.push_back(std::move(loaded.image));
    encoded_.push_back(std::move(loaded.encoded));
  }
}

ImagesSource::~ImagesSource() { stop(); }

void ImagesSource::start(FrameCallback on_frame) {
  {
    std::lock_guard lock(health_mutex_);
    health_.connected = true;
  }
  thread_.start([this, on_frame = std::move(on_frame)] { run(on_frame); });
}

void ImagesSource::stop() {
  thread_.stop();
  std::lock_guard lock(health_mutex_);
  health_.connected = false;
}

SourceHealth ImagesSource::health() const {
  std::lock_guard lock(health_mutex_);
  return health_;
}

void ImagesSource::run(FrameCallback on_frame) {
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / rate_hz_));
  auto due = std::chrono::steady_clock::now();
  for (uint64_t sequence = 1;; ++sequence) {
    if (!thread_.wait_until(due)) return;
    auto frames = std::make_shared<FrameSet>();
    frames->sequence = sequence;
    frames->capture_time = std::chrono::system_clock::now();
    frames->arrival = std::chrono::steady_clock::now();
    frames->rig = rig_;
    frames->rig_version = 1;
    frames->images = images_;  // shares the pixel data; nobody writes to it
    frames->encoded = encoded_;
    on_frame(std::move(frames));
    {
      std::lock_guard lock(health_mutex_);
      ++health_.frames;
    }
    // Deadlines step from the last deadline, not from now, so the rate does not drift;
    // after a stall (a slow machine) restart from now instead of bursting to catch up.
    due += period;
    const auto now = std::chrono::steady_clock::now();
    if (due + period < now) due = now;
  }
}

std::unique_ptr<Source> make_images_source(const SourceConfig& config) {
  return std::make_unique<ImagesSource>(config);
}

}  // namespace omniview
