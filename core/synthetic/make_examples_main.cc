// Renders the bundled example images: what the two lenses of
// config/examples/dual_fisheye/rig.yaml see in the synthetic room (Scene::room). Run it
// when the rig or the room changes:  omniview_make_examples [FOLDER holding rig.yaml]
// (default: the source tree's config/examples/dual_fisheye).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/io/image_codec.h"
#include "core/rig/rig.h"
#include "core/synthetic/render.h"

namespace {

// Keeps the repository small: JPEG quality 90 unless that file would exceed the budget.
constexpr size_t kMaxBytes = 250 * 1024;

void write_jpeg(const cv::Mat& image, const std::filesystem::path& path) {
  std::vector<uint8_t> bytes;
  for (int quality = 90; quality >= 50; quality -= 5) {
    bytes = omniview::encode_jpeg(image, quality);
    if (bytes.size() <= kMaxBytes) break;
  }
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0) {
    throw std::runtime_error("cannot write " + path.string());
  }
  std::cout << "wrote " << path.string() << " (" << bytes.size() / 1024 << " KiB)\n";
}

constexpr const char* kUsage = R"(usage: omniview_make_examples [FOLDER]

Renders what each camera of FOLDER/rig.yaml sees in the synthetic room and writes
FOLDER/CAMERA.jpg per camera. FOLDER defaults to the source tree's
config/examples/dual_fisheye (the bundled example images).
)";

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  const auto is_help = [](const std::string& a) { return a == "--help" || a == "-h"; };
  if (std::any_of(args.begin(), args.end(), is_help)) {
    std::cout << kUsage;
    return 0;
  }
  if (args.size() > 1 || (!args.empty() && args[0].rfind("-", 0) == 0)) {  // a mistyped option is no folder
    std::cerr << kUsage;
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
