// Renders the bundled example images: what the two lenses of
// config/examples/dual_fisheye/rig.yaml see in the synthetic room (Scene::room). Run it
// when the rig or the room changes:  omniview_make_examples [FOLDER holding rig.yaml]
// (default: the source tree's config/examples/dual_fisheye).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "core/rig/rig.h"
#include "core/synthetic/render.h"

namespace {

// Keeps the repository small: JPEG quality 90 unless that file would exceed the budget.
constexpr size_t kMaxBytes = 250 * 1024;

void write_jpeg(const cv::Mat& image, const std::filesystem::path& path) {
  std::vector<uchar> bytes;
  for (int quality = 90; quality >= 50; quality -= 5) {
    if (!cv::imencode(".jpg", image, bytes, {cv::IMWRITE_JPEG_QUALITY, quality})) {
      throw std::runtime_error("cannot encode " + path.string());
    }
    if (bytes.size() <= kMaxBytes) break;
  }
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0) {
    throw std::runtime_error("cannot write " + path.string());
  }
  std::cout << "wrote " << path.string() << " (" << bytes.size() / 1024 << " KiB)\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2) {
    std::cerr << "usage: omniview_make_examples [FOLDER holding rig.yaml]\n";
    return 2;
  }
  try {
    const std::filesystem::path folder =
        argc == 2 ? std::filesystem::path(argv[1])
                  : std::filesystem::path(OMNIVIEW_SOURCE_DIR) / "config/examples/dual_fisheye";
    const omniview::Rig rig = omniview::load_rig_yaml((folder / "rig.yaml").string());
    const auto scene = omniview::synthetic::Scene::room();
    for (size_t i = 0; i < rig.cameras().size(); ++i) {
      // 4x4 rays per pixel: the room's grid lines are sharper than the golden texture.
      const cv::Mat image = omniview::synthetic::render_camera(scene, rig, i, rig.default_frame(), {.supersample = 4});
      write_jpeg(image, folder / (rig.cameras()[i].name + ".jpg"));
    }
  } catch (const std::exception& e) {
    std::cerr << "omniview_make_examples: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
