// Renders the bundled example images: what the two lenses of
// config/examples/dual_fisheye/rig.yaml see in the synthetic room. Run by hand when the
// rig or the scene changes:  omniview_make_examples config/examples/dual_fisheye
#include <filesystem>
#include <iostream>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "core/rig/rig.h"
#include "core/synthetic/render.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: omniview_make_examples FOLDER (holding rig.yaml)\n";
    return 2;
  }
  try {
    const std::filesystem::path folder(argv[1]);
    const omniview::Rig rig = omniview::load_rig_yaml((folder / "rig.yaml").string());
    const auto scene = omniview::synthetic::Scene::room();
    for (size_t i = 0; i < rig.cameras().size(); ++i) {
      const cv::Mat image = omniview::synthetic::render_camera(scene, rig, i, rig.default_frame());
      const auto path = (folder / (rig.cameras()[i].name + ".jpg")).string();
      if (!cv::imwrite(path, image, {cv::IMWRITE_JPEG_QUALITY, 90})) throw std::runtime_error("cannot write " + path);
      std::cout << "wrote " << path << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "omniview_make_examples: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
