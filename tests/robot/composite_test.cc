// Compositing a layer over BGR and grey images: exact values at opacity 0, 0.5 and 1.
#include <gtest/gtest.h>

#include "core/robot/overlay/composite.h"

namespace omniview::robot {
namespace {

// 8x6 layer: colour (B, G, R) = (200, 250, 0); alpha 255 at (2, 1), 128 at (3, 1),
// 255 at (5, 4); 0 elsewhere.
OverlayLayer synthetic_layer() {
  OverlayLayer layer;
  layer.bgra = cv::Mat(6, 8, CV_8UC4, cv::Scalar(200, 250, 0, 0));
  layer.bgra.at<cv::Vec4b>(1, 2)[3] = 255;
  layer.bgra.at<cv::Vec4b>(1, 3)[3] = 128;
  layer.bgra.at<cv::Vec4b>(4, 5)[3] = 255;
  layer.bbox = alpha_bounding_box(layer.bgra);
  return layer;
}

TEST(Composite, BoundingBoxOfAlpha) {
  EXPECT_EQ(synthetic_layer().bbox, cv::Rect(2, 1, 4, 4));
  EXPECT_TRUE(alpha_bounding_box(cv::Mat(3, 3, CV_8UC4, cv::Scalar::all(0))).empty());
}

TEST(Composite, ExactValuesOnBgr) {
  const OverlayLayer layer = synthetic_layer();
  const cv::Mat background(6, 8, CV_8UC3, cv::Scalar(100, 50, 200));
  const auto run = [&](double opacity) {
    cv::Mat image = background.clone();
    composite(layer, image, opacity);
    return image;
  };
  EXPECT_EQ(cv::norm(run(0.0), background, cv::NORM_INF), 0);

  const cv::Mat full = run(1.0);
  EXPECT_EQ(full.at<cv::Vec3b>(1, 2), cv::Vec3b(200, 250, 0));
  EXPECT_EQ(full.at<cv::Vec3b>(4, 5), cv::Vec3b(200, 250, 0));
  // Alpha 128: weight round(128 * 256 / 255) = 129 of 256.
  EXPECT_EQ(full.at<cv::Vec3b>(1, 3), cv::Vec3b((100 * 127 + 200 * 129 + 128) >> 8, (50 * 127 + 250 * 129 + 128) >> 8,
                                                (200 * 127 + 128) >> 8));
  EXPECT_EQ(full.at<cv::Vec3b>(1, 3), cv::Vec3b(150, 151, 99));

  const cv::Mat half = run(0.5);
  EXPECT_EQ(half.at<cv::Vec3b>(1, 2), cv::Vec3b(150, 150, 100));  // (a + b + 1) / 2
  EXPECT_EQ(half.at<cv::Vec3b>(1, 3), cv::Vec3b(125, 100, 150));  // weight 64

  // Transparent pixels stay exactly as they were, inside and outside the box.
  for (const cv::Mat& image : {full, half}) {
    cv::Mat changed = image != background;
    cv::Mat any;
    cv::reduce(changed.reshape(1, 6 * 8), any, 1, cv::REDUCE_MAX);
    EXPECT_EQ(cv::countNonZero(any), 3);
  }
}

TEST(Composite, ExactValuesOnGrey) {
  const OverlayLayer layer = synthetic_layer();
  cv::Mat image(6, 8, CV_8UC1, cv::Scalar(80));
  composite(layer, image, 1.0);
  const int luma = (29 * 200 + 150 * 250 + 77 * 0 + 128) >> 8;
  EXPECT_EQ(luma, 169);
  EXPECT_EQ(image.at<uint8_t>(1, 2), luma);
  EXPECT_EQ(image.at<uint8_t>(0, 0), 80);
  image.setTo(80);
  composite(layer, image, 0.5);
  EXPECT_EQ(image.at<uint8_t>(1, 2), 125);  // (80 * 128 + 169 * 128 + 128) >> 8
  image.setTo(80);
  composite(layer, image, 0.0);
  EXPECT_EQ(cv::countNonZero(image != 80), 0);
}

TEST(Composite, RejectsMismatchedImages) {
  const OverlayLayer layer = synthetic_layer();
  cv::Mat small(5, 8, CV_8UC3), rgba(6, 8, CV_8UC4);
  EXPECT_THROW(composite(layer, small, 1.0), std::invalid_argument);
  EXPECT_THROW(composite(layer, rgba, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace omniview::robot
