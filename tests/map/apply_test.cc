// apply_map against a plain double-precision bilinear sampler, on hand-made maps that reach
// every corner of the images (the last footprint, black pixels, rows whose length is no
// multiple of the SIMD width), for grey and colour, mixed inputs and blending.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/map/apply.h"
#include "core/map/apply_avx2.h"
#include "core/map/fusion_map.h"

namespace omniview {
namespace {

// Two cameras of different sizes; map entries drawn at random, plus every extreme footprint.
FusionMap random_map(int w, int h, const std::vector<cv::Size>& sizes, uint64_t seed) {
  FusionMap map;
  map.width = w, map.height = h;
  map.camera_sizes = sizes;
  for (size_t i = 0; i < sizes.size(); ++i) map.camera_names.push_back("cam" + std::to_string(i));
  map.camera_used.assign(sizes.size(), true);
  cv::RNG rng(seed);
  map.primary.resize(static_cast<size_t>(w) * h);
  for (size_t i = 0; i < map.primary.size(); ++i) {
    MapEntry e = kBlackEntry;
    const int cam = rng.uniform(0, static_cast<int>(sizes.size()) + 1);
    if (cam < static_cast<int>(sizes.size())) {
      const cv::Size s = sizes[cam];
      int x0 = rng.uniform(0, s.width - 1), y0 = rng.uniform(0, s.height - 1);
      switch (i % 7) {  // the image's corners, where a wide read would leave it
        case 0: x0 = s.width - 2, y0 = s.height - 2; break;
        case 1: x0 = 0, y0 = 0; break;
        case 2: x0 = s.width - 2; break;
        default: break;
      }
      e.offset = static_cast<uint32_t>(y0 * s.width + x0);
      e.fx = static_cast<uint8_t>(rng.uniform(0, 256));
      e.fy = static_cast<uint8_t>(rng.uniform(0, 256));
      e.cam = static_cast<uint8_t>(cam);
    }
    map.primary[i] = e;
  }
  return map;
}

// Channel c of camera image `img` at the entry's position, bilinear in double.
double reference(const cv::Mat& img, const MapEntry& e, int c, int out_channels) {
  const int x0 = static_cast<int>(e.offset % img.cols), y0 = static_cast<int>(e.offset / img.cols);
  const double fx = e.fx / 256.0, fy = e.fy / 256.0;
  const auto at = [&](int x, int y) {
    if (img.channels() == 1) return static_cast<double>(img.at<uint8_t>(y, x));
    const cv::Vec3b p = img.at<cv::Vec3b>(y, x);
    if (out_channels == 3) return static_cast<double>(p[c]);
    return (29.0 * p[0] + 150.0 * p[1] + 77.0 * p[2]) / 256.0;
  };
  return (at(x0, y0) * (1 - fx) + at(x0 + 1, y0) * fx) * (1 - fy) + (at(x0, y0 + 1) * (1 - fx) + at(x0 + 1, y0 + 1) * fx) * fy;
}

std::vector<cv::Mat> random_images(const std::vector<cv::Size>& sizes, int type) {
  std::vector<cv::Mat> images;
  cv::RNG rng(7);
  for (const auto& s : sizes) {
    images.emplace_back(s, type);
    rng.fill(images.back(), cv::RNG::UNIFORM, 0, 256);
  }
  return images;
}

void expect_matches_reference_once(const FusionMap& map, const std::vector<cv::Mat>& images, int out_channels) {
  cv::Mat out;
  apply_map(map, images, out, out_channels);
  ASSERT_EQ(out.rows, map.height);
  ASSERT_EQ(out.cols, map.width);
  int worst = 0;
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const MapEntry& e = map.primary[static_cast<size_t>(y) * map.width + x];
      for (int c = 0; c < out_channels; ++c) {
        const int got = out.ptr<uint8_t>(y)[x * out_channels + c];
        const int want = e.cam == kNoCamera ? 0 : static_cast<int>(std::lround(reference(images[e.cam], e, c, out_channels)));
        worst = std::max(worst, std::abs(got - want));
        ASSERT_LE(std::abs(got - want), 1) << "pixel (" << x << ", " << y << ") channel " << c;
      }
    }
  }
  ::testing::Test::RecordProperty("worst_difference", worst);
}

void expect_matches_reference(const FusionMap& map, const std::vector<cv::Mat>& images, int out_channels) {
  for (bool simd : {true, false}) {
    SCOPED_TRACE(simd ? "SIMD rows" : "portable rows");
    apply_internal::set_simd_enabled(simd);
    expect_matches_reference_once(map, images, out_channels);
  }
  apply_internal::set_simd_enabled(true);
}

const std::vector<cv::Size> kSizes = {{37, 23}, {64, 48}};

TEST(ApplyMap, ColourMatchesBilinearReference) {
  for (int w : {1, 7, 8, 9, 61}) {
    const FusionMap map = random_map(w, 13, kSizes, 100 + w);
    expect_matches_reference(map, random_images(kSizes, CV_8UC3), 3);
  }
}

TEST(ApplyMap, GreyMatchesBilinearReference) {
  for (int w : {1, 7, 8, 9, 61}) {
    const FusionMap map = random_map(w, 13, kSizes, 200 + w);
    expect_matches_reference(map, random_images(kSizes, CV_8UC1), 1);
  }
}

TEST(ApplyMap, ColourToGreyAndGreyToColour) {
  const FusionMap map = random_map(33, 9, kSizes, 300);
  expect_matches_reference(map, random_images(kSizes, CV_8UC3), 1);
  expect_matches_reference(map, random_images(kSizes, CV_8UC1), 3);
}

TEST(ApplyMap, UnusedCamerasMayBeEmpty) {
  FusionMap map = random_map(40, 10, kSizes, 400);
  for (auto& e : map.primary) {
    if (e.cam == 1) e = kBlackEntry;
  }
  map.camera_used = {true, false};
  auto images = random_images(kSizes, CV_8UC3);
  images[1] = cv::Mat();
  expect_matches_reference(map, images, 3);
}

TEST(ApplyMap, NonContinuousImagesAreSampledCorrectly) {
  const FusionMap map = random_map(29, 11, kSizes, 500);
  std::vector<cv::Mat> images;
  for (const cv::Mat& img : random_images({{50, 30}, {80, 60}}, CV_8UC3)) {
    images.push_back(img(cv::Rect(3, 2, kSizes[images.size()].width, kSizes[images.size()].height)));
  }
  expect_matches_reference(map, images, 3);
}

// Entries at pyramid levels read cv::pyrDown's images (footprint.h), built by apply_map.
TEST(ApplyMap, PyramidLevelsReadPyrDownImages) {
  for (int channels : {1, 3}) {
    const auto images = random_images(kSizes, channels == 3 ? CV_8UC3 : CV_8UC1);
    FusionMap map = random_map(45, 12, kSizes, 600 + channels);
    std::vector<std::vector<cv::Mat>> pyramids(kSizes.size());
    for (size_t c = 0; c < kSizes.size(); ++c) cv::buildPyramid(images[c], pyramids[c], 2);
    map.camera_levels = {2, 1};
    cv::RNG rng(9);
    for (auto& e : map.primary) {
      if (e.cam == kNoCamera) continue;
      e.level = static_cast<uint8_t>(rng.uniform(0, map.camera_levels[e.cam] + 1));
      const cv::Size s = pyramids[e.cam][e.level].size();
      e.offset = static_cast<uint32_t>(rng.uniform(0, s.height - 1) * s.width + rng.uniform(0, s.width - 1));
    }
    for (bool simd : {true, false}) {
      apply_internal::set_simd_enabled(simd);
      cv::Mat out;
      apply_map(map, images, out, channels);
      for (int y = 0; y < map.height; ++y) {
        for (int x = 0; x < map.width; ++x) {
          const MapEntry& e = map.primary[static_cast<size_t>(y) * map.width + x];
          for (int c = 0; c < channels; ++c) {
            const int got = out.ptr<uint8_t>(y)[x * channels + c];
            const int want =
                e.cam == kNoCamera ? 0 : static_cast<int>(std::lround(reference(pyramids[e.cam][e.level], e, c, channels)));
            ASSERT_LE(std::abs(got - want), 1) << (simd ? "SIMD" : "portable") << " pixel (" << x << ", " << y << ")";
          }
        }
      }
    }
    apply_internal::set_simd_enabled(true);
  }
}

}  // namespace
}  // namespace omniview
