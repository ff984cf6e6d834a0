// The `images` source: loads and checks once, then delivers at its rate.
#include <fstream>

#include <opencv2/core.hpp>

#include "core/io/image_codec.h"
#include "server/sources/builtin_sources.h"
#include "server/sources/images_source.h"
#include "tests/sources/source_test_support.h"

namespace omniview {
namespace {
using namespace omniview::testing;
using namespace std::chrono_literals;

const std::string kExample = OMNIVIEW_SOURCE_DIR "/config/examples/dual_fisheye";

std::string example_yaml(const std::string& extra = "rate_hz: 50\n") {
  return "name: still\ntype: images\nrig: rig.yaml\nimages:\n  front: front.jpg\n  back: back.jpg\n" + extra;
}

TEST(ImagesSource, DeliversAtRateWithIncreasingSequence) {
  TestConfig config(example_yaml(), kExample);
  ImagesSource source(config.config);
  EXPECT_EQ(source.type(), "images");
  ASSERT_EQ(source.rig()->cameras().size(), 2u);
  Collector collector;
  const auto start = std::chrono::steady_clock::now();
  source.start(collector.callback());
  const auto frames = collector.wait_for(11, 2s);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  source.stop();
  ASSERT_GE(frames.size(), 11u);
  // 10 intervals at 50 Hz: 0.2 s (loose bounds: a loaded test machine).
  EXPECT_GT(elapsed, 0.15);
  EXPECT_LT(elapsed, 0.6);
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i]->sequence, i + 1);
    EXPECT_EQ(frames[i]->rig, source.rig());
    ASSERT_EQ(frames[i]->images.size(), 2u);
    EXPECT_EQ(frames[i]->images[0].size(), cv::Size(1024, 1024));
    EXPECT_EQ(frames[i]->images[1].type(), CV_8UC3);
  }
  EXPECT_GE(source.health().frames, 11u);
  EXPECT_FALSE(source.health().connected);
  // No callback after stop() returned.
  const size_t after_stop = collector.count();
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(collector.count(), after_stop);
  source.stop();  // twice is fine
}

std::vector<uint8_t> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(ImagesSource, KeepsJpegAndPngFilesAsTheyAre) {
  // front as the JPEG it is, back as a PNG: both kept as their files' bytes besides the pixels.
  TempFolder dir;
  const cv::Mat back = read_image(kExample + "/back.jpg", ImageColour::kBgr);
  write_image(dir.str() + "/back.png", back);
  {
    const std::string back_file = dir.str() + "/back.png";
    TestConfig config("name: still\ntype: images\nrig: rig.yaml\nimages:\n  front: front.jpg\n  back: " + back_file +
                          "\nrate_hz: 50\n",
                      kExample);
    ImagesSource source(config.config);
    Collector collector;
    source.start(collector.callback());
    const auto frames = collector.wait_for(1, 2s);
    source.stop();
    ASSERT_FALSE(frames.empty());
    const FrameSet& f = *frames[0];
    ASSERT_EQ(f.encoded.size(), 2u);
    EXPECT_EQ(f.encoded[0].format, "jpeg");
    ASSERT_TRUE(f.encoded[0].bytes);
    EXPECT_EQ(*f.encoded[0].bytes, file_bytes(kExample + "/front.jpg")) << "byte for byte, not re-encoded";
    EXPECT_EQ(cv::norm(f.images[1], back, cv::NORM_INF), 0) << "decoded as the file says";
    EXPECT_EQ(f.encoded[1].format, "png");
    ASSERT_TRUE(f.encoded[1].bytes);
    EXPECT_EQ(*f.encoded[1].bytes, file_bytes(back_file));
  }
}

TEST(ImagesSource, RegisteredAsBuiltin) {
  register_builtin_sources();
  TestConfig config(example_yaml(), kExample);
  const auto source = make_source("images", config.config);
  EXPECT_EQ(source->type(), "images");
  bool has_replay = false;
  for (const auto& [type, help] : source_types()) has_replay |= type == "replay";
  EXPECT_TRUE(has_replay);
}

TEST(ImagesSource, ErrorsNameFileLineAndKey) {
  const auto error = [](const std::string& yaml, const std::string& folder = kExample) {
    return config_error([&] {
      TestConfig config(yaml, folder);
      ImagesSource source(config.config);
    });
  };
  std::string e = error(example_yaml("rate: 5\n"));
  EXPECT_TRUE(contains(e, "daemon.yaml:7")) << e;
  EXPECT_TRUE(contains(e, "rate")) << e;
  e = error("name: s\ntype: images\nrig: rig.yaml\nimages:\n  front: front.jpg\n");
  EXPECT_TRUE(contains(e, "daemon.yaml:5")) << e;
  EXPECT_TRUE(contains(e, "back")) << e;
  e = error(example_yaml("  side: front.jpg\n"));
  EXPECT_TRUE(contains(e, "sources[0].images.side")) << e;
  e = error(example_yaml("rate_hz: -3\n"));
  EXPECT_TRUE(contains(e, "sources[0].rate_hz")) << e;
  e = error("name: s\ntype: images\nimages: {}\n");
  EXPECT_TRUE(contains(e, "rig")) << e;
  e = error("name: s\ntype: images\nrig: nowhere.yaml\nimages: {}\n");
  EXPECT_TRUE(contains(e, "nowhere.yaml")) << e;
}

TEST(ImagesSource, CorruptOrWrongSizeImageNamesFileAndCamera) {
  TempFolder dir;
  std::ofstream(dir / "broken.jpg") << "not a jpeg";
  write_image(dir / "small.png", cv::Mat(8, 8, CV_8UC3, cv::Scalar(0, 0, 0)));
  const auto error = [&](const std::string& back) {
    return config_error([&] {
      TestConfig config("name: s\ntype: images\nrig: " + kExample + "/rig.yaml\nimages:\n  front: " + kExample +
                            "/front.jpg\n  back: " + back + "\n",
                        dir.str());
      ImagesSource source(config.config);
    });
  };
  std::string e = error("broken.jpg");
  EXPECT_TRUE(contains(e, "daemon.yaml:6")) << e;
  EXPECT_TRUE(contains(e, dir / "broken.jpg")) << e;
  EXPECT_TRUE(contains(e, "camera 'back'")) << e;
  EXPECT_TRUE(contains(e, "neither PNG nor JPEG data")) << e;
  e = error("small.png");
  EXPECT_TRUE(contains(e, "8x8")) << e;
  EXPECT_TRUE(contains(e, "1024x1024")) << e;
}

TEST(ImagesSource, KalibrCamchainWithFrameAndPose) {
  TempFolder dir;
  std::ofstream(dir / "camchain.yaml") << "cam0:\n  camera_model: pinhole\n  intrinsics: [20, 20, 15.5, 11.5]\n"
                                          "  distortion_model: none\n  resolution: [32, 24]\n";
  write_image(dir / "cam0.png", cv::Mat(24, 32, CV_8UC1, cv::Scalar(9)));
  TestConfig config(
      "name: s\ntype: images\nrig: camchain.yaml\nrig_frame: mast\nrig_pose: [0.1, 0, 1, 90, 0, 0]\n"
      "images: {cam0: cam0.png}\nrate_hz: 100\n",
      dir.str());
  ImagesSource source(config.config);
  const Camera& cam = source.rig()->cameras()[0];
  EXPECT_EQ(cam.parent_frame, "mast");
  EXPECT_NEAR(cam.T_parent_cam.translation().z(), 1.0, 1e-12);
  Collector collector;
  source.start(collector.callback());
  const auto frames = collector.wait_for(2, 2s);
  source.stop();
  ASSERT_GE(frames.size(), 2u);
  EXPECT_EQ(frames[0]->images[0].type(), CV_8UC1);
}

}  // namespace
}  // namespace omniview
