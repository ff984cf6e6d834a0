// The bundled example (config/examples): its images must be what its rig sees of the
// synthetic room, and every bundled view must render from them with full coverage.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include <opencv2/core.hpp>

#include "core/io/image_codec.h"
#include "core/map/apply.h"
#include "core/synthetic/render.h"
#include "core/view/view.h"
#include "core/view/view_yaml.h"
#include "tests/golden/golden.h"

namespace omniview {
namespace {

std::vector<cv::Mat> example_images(const Rig& rig) {
  std::vector<cv::Mat> images;
  for (const Camera& c : rig.cameras()) {
    images.push_back(read_image(golden::example_dir() + "/" + c.name + ".jpg", ImageColour::kBgr));
  }
  return images;
}

TEST(Examples, ImagesAreWhatTheRigSeesOfTheRoom) {
  // Fails when rig.yaml or Scene::room() changed without rerunning omniview_make_examples.
  const Rig rig = golden::example_rig();
  const auto images = example_images(rig);
  const auto room = synthetic::Scene::room();
  for (size_t i = 0; i < rig.cameras().size(); ++i) {
    ASSERT_FALSE(images[i].empty()) << rig.cameras()[i].name;
    const cv::Mat fresh = synthetic::render_camera(room, rig, i, rig.default_frame(), {.supersample = 2});
    ASSERT_EQ(fresh.size(), images[i].size());
    const double psnr = cv::PSNR(fresh, images[i]);
    std::cout << "[ golden ] example " << rig.cameras()[i].name << ".jpg vs a fresh render: " << psnr << " dB\n";
    EXPECT_GT(psnr, 38) << rig.cameras()[i].name;  // JPEG q90, 2x2 vs 4x4 supersampling: measured 42.5
  }
}

TEST(Examples, EveryBundledViewRendersFromTheExampleImages) {
  const Rig rig = golden::example_rig();
  const auto images = example_images(rig);
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(OMNIVIEW_SOURCE_DIR "/config/examples/views")) {
    if (e.path().extension() == ".yaml") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 5u);
  for (const auto& file : files) {
    for (const ViewSpec& spec : load_views(file.string())) {
      const auto view = View::create(spec);
      const FusionMap map = build_map(rig, *view);
      cv::Mat out;
      apply_map(map, images, out, 3);
      ASSERT_EQ(out.size(), cv::Size(spec.width, spec.height)) << file;
      size_t surface = 0, covered = 0;
      for (int v = 0; v < spec.height; ++v) {
        for (int u = 0; u < spec.width; ++u) {
          Vec3 p;
          if (!view->pixel_to_point(u, v, p)) continue;
          ++surface;
          covered += map.primary[static_cast<size_t>(v) * spec.width + u].cam != kNoCamera;
        }
      }
      EXPECT_GT(double(covered) / surface, 0.999) << file << ": the two 210 deg lenses see everything";
    }
  }
}

}  // namespace
}  // namespace omniview
