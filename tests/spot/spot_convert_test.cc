// Robot data -> omniview types: camera models, frame trees, images, the rig and its
// footprint frame. Everything here is outside data, so the bad cases matter most.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "core/io/image_codec.h"
#include "spot_adapter/client/spot_error.h"
#include "spot_adapter/convert/camera_model_from_source.h"
#include "spot_adapter/convert/depth_from_response.h"
#include "spot_adapter/convert/frame_tree.h"
#include "spot_adapter/convert/image_from_response.h"
#include "spot_adapter/source/spot_rig.h"

namespace omniview::spot {
namespace {

namespace api = bosdyn::api;

void set_pinhole(api::ImageSource::PinholeModel::CameraIntrinsics* in, double f, double cx, double cy) {
  in->mutable_focal_length()->set_x(f);
  in->mutable_focal_length()->set_y(f);
  in->mutable_principal_point()->set_x(cx);
  in->mutable_principal_point()->set_y(cy);
}

api::ImageSource pinhole_source(const std::string& name = "frontleft_fisheye_image") {
  api::ImageSource s;
  s.set_name(name);
  s.set_cols(640);
  s.set_rows(480);
  set_pinhole(s.mutable_pinhole()->mutable_intrinsics(), 330, 319.5, 239.5);
  return s;
}

template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const SpotError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(CameraFromImageSource, PinholeBrownConradyAndKannalaBrandt) {
  const Camera pin = camera_from_image_source(pinhole_source());
  EXPECT_EQ(pin.width, 640);
  EXPECT_EQ(pin.height, 480);
  ASSERT_TRUE(std::holds_alternative<PinholeRadtan>(pin.model));
  EXPECT_DOUBLE_EQ(std::get<PinholeRadtan>(pin.model).fu(), 330);
  EXPECT_TRUE(std::get<PinholeRadtan>(pin.model).distortion().is_zero());

  api::ImageSource bc = pinhole_source("hand_color_image");
  auto* bi = bc.mutable_pinhole_brown_conrady()->mutable_intrinsics();
  set_pinhole(bi->mutable_pinhole_intrinsics(), 500, 320, 240);
  bi->set_k1(-0.2f), bi->set_k2(0.05f), bi->set_p1(0.001f), bi->set_p2(-0.001f), bi->set_k3(0.01f);
  const Camera brown = camera_from_image_source(bc);
  ASSERT_TRUE(std::holds_alternative<PinholeRadtan>(brown.model));
  EXPECT_FLOAT_EQ(static_cast<float>(std::get<PinholeRadtan>(brown.model).distortion().k3), 0.01f);

  api::ImageSource kb = pinhole_source("fisheye");
  auto* ki = kb.mutable_kannala_brandt()->mutable_intrinsics();
  set_pinhole(ki->mutable_pinhole_intrinsics(), 200, 320, 240);
  ki->set_k1(0.01f);
  const Camera fisheye = camera_from_image_source(kb);
  EXPECT_TRUE(std::holds_alternative<Equidistant>(fisheye.model));
}

TEST(CameraFromImageSource, ImpossibleCalibrationsNameTheSource) {
  api::ImageSource none = pinhole_source("left_fisheye_image");
  none.clear_pinhole();
  EXPECT_NE(error_of([&] { camera_from_image_source(none); }).find("'left_fisheye_image': reports no camera model"),
            std::string::npos);
  api::ImageSource zero = pinhole_source("back_fisheye_image");
  set_pinhole(zero.mutable_pinhole()->mutable_intrinsics(), 0, 319.5, 239.5);
  EXPECT_NE(error_of([&] { camera_from_image_source(zero); }).find("back_fisheye_image"), std::string::npos);
  api::ImageSource huge = pinhole_source("right_fisheye_image");
  huge.set_cols(1 << 20);
  EXPECT_NE(error_of([&] { camera_from_image_source(huge); }).find("image size"), std::string::npos);
  api::ImageSource nan = pinhole_source("x");
  set_pinhole(nan.mutable_pinhole()->mutable_intrinsics(), std::nan(""), 1, 1);
  EXPECT_NE(error_of([&] { camera_from_image_source(nan); }), "(no error)");
}

void add_edge(api::FrameTreeSnapshot& tree, const std::string& child, const std::string& parent, const Vec3& t,
              const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  auto& e = (*tree.mutable_child_to_parent_edge_map())[child];
  e.set_parent_frame_name(parent);
  auto* p = e.mutable_parent_tform_child();
  p->mutable_position()->set_x(t.x()), p->mutable_position()->set_y(t.y()), p->mutable_position()->set_z(t.z());
  p->mutable_rotation()->set_w(q.w()), p->mutable_rotation()->set_x(q.x());
  p->mutable_rotation()->set_y(q.y()), p->mutable_rotation()->set_z(q.z());
}

TEST(FrameTree, EdgesSortedRootsSkippedBadPosesRefused) {
  api::FrameTreeSnapshot tree;
  (*tree.mutable_child_to_parent_edge_map())["body"];  // the root: no parent
  add_edge(tree, "vision", "body", Vec3(0, 0, -0.5));
  add_edge(tree, "frontleft", "body", Vec3(0.4, 0, 0));
  const auto edges = frame_edges(tree, "test");
  ASSERT_EQ(edges.size(), 2u);
  EXPECT_EQ(edges[0].child, "frontleft");
  EXPECT_NEAR(edges[1].T_parent_child.translation().z(), -0.5, 1e-12);

  add_edge(tree, "odom", "body", Vec3(0, 0, 0), Eigen::Quaterniond(2, 0, 0, 0));
  EXPECT_NE(error_of([&] { frame_edges(tree, "test"); }).find("frame 'odom'"), std::string::npos);
  tree.mutable_child_to_parent_edge_map()->erase("odom");
  add_edge(tree, "gpe", "body", Vec3(std::nan(""), 0, 0));
  EXPECT_NE(error_of([&] { frame_edges(tree, "test"); }).find("not finite"), std::string::npos);
}

api::ImageResponse response(const cv::Mat& image, api::Image::Format format, api::Image::PixelFormat pixels) {
  api::ImageResponse r;
  r.set_status(api::ImageResponse::STATUS_OK);
  auto* img = r.mutable_shot()->mutable_image();
  img->set_cols(image.cols);
  img->set_rows(image.rows);
  img->set_format(format);
  img->set_pixel_format(pixels);
  if (format == api::Image::FORMAT_JPEG) {
    const std::vector<uint8_t> bytes = encode_jpeg(image, 95);
    img->set_data(bytes.data(), bytes.size());
  } else {
    img->set_data(image.data, image.total() * image.elemSize());
  }
  return r;
}

cv::Mat gradient(int w, int h, int channels) {
  cv::Mat m(h, w, CV_8UC(channels));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w * channels; ++x) m.at<uint8_t>(y, x) = static_cast<uint8_t>((x * 3 + y * 5) % 256);
  }
  return m;
}

TEST(ImageFromResponse, JpegKeepsTheRobotsBytesRawIsCopiedRgbBecomesBgr) {
  const cv::Mat grey = gradient(64, 48, 1);
  const auto jpeg = response(grey, api::Image::FORMAT_JPEG, api::Image::PIXEL_FORMAT_GREYSCALE_U8);
  const DecodedImage d = decode_image_response(jpeg, "frontleft_fisheye", 64, 48);
  EXPECT_EQ(d.image.type(), CV_8UC1);
  EXPECT_EQ(d.encoded.format, "jpeg");
  ASSERT_TRUE(d.encoded.bytes);
  EXPECT_EQ(d.encoded.bytes->size(), jpeg.shot().image().data().size());
  EXPECT_LT(cv::norm(d.image, grey, cv::NORM_L1) / grey.total(), 3.0);

  const DecodedImage raw =
      decode_image_response(response(grey, api::Image::FORMAT_RAW, api::Image::PIXEL_FORMAT_GREYSCALE_U8), "c", 64, 48);
  EXPECT_EQ(cv::norm(raw.image, grey, cv::NORM_INF), 0);
  EXPECT_TRUE(raw.encoded.format.empty());

  cv::Mat rgb(2, 2, CV_8UC3, cv::Scalar(10, 20, 30));  // R=10 G=20 B=30 as the robot sends it
  const DecodedImage colour =
      decode_image_response(response(rgb, api::Image::FORMAT_RAW, api::Image::PIXEL_FORMAT_RGB_U8), "c", 2, 2);
  EXPECT_EQ(colour.image.at<cv::Vec3b>(0, 0), cv::Vec3b(30, 20, 10));
}

TEST(ImageFromResponse, BadResponsesAreClearErrorsNamingTheCamera) {
  const cv::Mat grey = gradient(64, 48, 1);
  auto status = response(grey, api::Image::FORMAT_JPEG, api::Image::PIXEL_FORMAT_GREYSCALE_U8);
  status.set_status(api::ImageResponse::STATUS_IMAGE_DATA_ERROR);
  EXPECT_NE(error_of([&] { decode_image_response(status, "left", 64, 48); }).find("camera 'left': the robot answered STATUS_IMAGE_DATA_ERROR"),
            std::string::npos);

  auto wrong_size = response(grey, api::Image::FORMAT_JPEG, api::Image::PIXEL_FORMAT_GREYSCALE_U8);
  EXPECT_NE(error_of([&] { decode_image_response(wrong_size, "left", 640, 480); }).find("calibrated for 640x480"),
            std::string::npos);

  auto lying = response(grey, api::Image::FORMAT_JPEG, api::Image::PIXEL_FORMAT_GREYSCALE_U8);
  lying.mutable_shot()->mutable_image()->set_cols(32);
  EXPECT_NE(error_of([&] { decode_image_response(lying, "left", 32, 48); }).find("JPEG is 64x48"), std::string::npos);

  auto truncated = response(grey, api::Image::FORMAT_JPEG, api::Image::PIXEL_FORMAT_GREYSCALE_U8);
  truncated.mutable_shot()->mutable_image()->mutable_data()->resize(120);
  EXPECT_NE(error_of([&] { decode_image_response(truncated, "left", 64, 48); }), "(no error)");

  // Cut in the middle of its scan data: libjpeg decodes the top and fills the rest grey,
  // with only a warning. That is an error too, never a picture with a grey patch.
  cv::Mat noise(240, 320, CV_8UC1);
  cv::randu(noise, 0, 256);
  auto cut = response(noise, api::Image::FORMAT_JPEG, api::Image::PIXEL_FORMAT_GREYSCALE_U8);
  cut.mutable_shot()->mutable_image()->mutable_data()->resize(cut.shot().image().data().size() * 2 / 3);
  EXPECT_NE(error_of([&] { decode_image_response(cut, "left", 320, 240); }).find("camera 'left': damaged JPEG"),
            std::string::npos)
      << error_of([&] { decode_image_response(cut, "left", 320, 240); });

  auto garbage = response(grey, api::Image::FORMAT_JPEG, api::Image::PIXEL_FORMAT_GREYSCALE_U8);
  garbage.mutable_shot()->mutable_image()->set_data("not a jpeg at all");
  EXPECT_NE(error_of([&] { decode_image_response(garbage, "left", 64, 48); }).find("corrupt JPEG"), std::string::npos);

  auto short_raw = response(grey, api::Image::FORMAT_RAW, api::Image::PIXEL_FORMAT_GREYSCALE_U8);
  short_raw.mutable_shot()->mutable_image()->mutable_data()->resize(100);
  EXPECT_NE(error_of([&] { decode_image_response(short_raw, "left", 64, 48); }).find("carries 100 bytes"), std::string::npos);

  auto depth = response(grey, api::Image::FORMAT_RAW, api::Image::PIXEL_FORMAT_DEPTH_U16);
  EXPECT_NE(error_of([&] { decode_image_response(depth, "left", 64, 48); }).find("not a visual image"), std::string::npos);
}

// A depth image as Spot sends it: RAW DEPTH_U16, little-endian, `scale` per metre.
api::ImageResponse depth_response(int cols, int rows, double scale, const std::vector<uint16_t>& values) {
  api::ImageResponse r;
  r.set_status(api::ImageResponse::STATUS_OK);
  *r.mutable_source() = pinhole_source("frontleft_depth_in_visual_frame");
  r.mutable_source()->set_depth_scale(scale);
  auto* img = r.mutable_shot()->mutable_image();
  img->set_cols(cols);
  img->set_rows(rows);
  img->set_format(api::Image::FORMAT_RAW);
  img->set_pixel_format(api::Image::PIXEL_FORMAT_DEPTH_U16);
  std::string bytes;
  for (uint16_t v : values) bytes += static_cast<char>(v & 0xff), bytes += static_cast<char>(v >> 8);
  img->set_data(bytes);
  return r;
}

TEST(DepthFromResponse, PointsAlongTheCameraRaysAtTheirDepthAndBadImagesNamed) {
  EXPECT_EQ(depth_source_for("frontleft_fisheye_image"), "frontleft_depth_in_visual_frame");
  EXPECT_EQ(depth_source_for("hand_image"), "hand_depth_in_visual_frame");
  Camera cam = camera_from_image_source(pinhole_source());
  cam.name = "frontleft_fisheye";
  // 640x480 all at 2.5 m but for the principal point's row, 0 (nothing measured) and 60 m.
  std::vector<uint16_t> values(640 * 480, 2500);
  for (int u = 0; u < 640; ++u) values[size_t(240) * 640 + u] = u < 320 ? 0 : 60000;
  const auto points = points_from_depth_response(depth_response(640, 480, 1000, values), cam, 4);
  ASSERT_EQ(points.size(), size_t(160 * 120 - 160));  // row 240 holds nothing usable
  for (const auto& p : points) EXPECT_NEAR(p.z(), 2.5f, 1e-4f);
  // Pixel (0, 0): (0 - 319.5) / 330 * 2.5 m to the left, and as far up.
  EXPECT_NEAR(points.front().x(), -319.5 / 330 * 2.5, 1e-4);
  EXPECT_NEAR(points.front().y(), -239.5 / 330 * 2.5, 1e-4);

  const auto error = [&](const api::ImageResponse& r) { return error_of([&] { points_from_depth_response(r, cam, 4); }); };
  EXPECT_NE(error(depth_response(320, 240, 1000, std::vector<uint16_t>(320 * 240))).find("depth of camera 'frontleft_fisheye': image is 320x240, the camera is calibrated for 640x480"),
            std::string::npos);
  EXPECT_NE(error(depth_response(640, 480, 1000, std::vector<uint16_t>(100))).find("carries 200 bytes"), std::string::npos);
  EXPECT_NE(error(depth_response(640, 480, 0, values)).find("no usable depth_scale"), std::string::npos);
  auto grey = depth_response(640, 480, 1000, values);
  grey.mutable_shot()->mutable_image()->set_pixel_format(api::Image::PIXEL_FORMAT_GREYSCALE_U8);
  EXPECT_NE(error(grey).find("expected RAW DEPTH_U16"), std::string::npos);
  auto refused = depth_response(640, 480, 1000, values);
  refused.set_status(api::ImageResponse::STATUS_UNKNOWN_CAMERA);
  EXPECT_NE(error(refused).find("STATUS_UNKNOWN_CAMERA"), std::string::npos);
}

TEST(SpotRig, CamerasHangInTheTreeAndFootprintSitsOnTheGround) {
  std::map<std::string, FrameEdge> tree;
  const auto edge = [&](const std::string& child, const std::string& parent, const Pose& T) {
    tree[child] = FrameEdge{child, parent, T};
  };
  Pose body_gpe = Pose::Identity();
  body_gpe.translation() = Vec3(0.3, -0.2, -0.52);  // the ground 0.52 m below the body
  edge("gpe", "body", body_gpe);
  Pose body_flat = Pose::Identity();
  edge("flat_body", "body", body_flat);
  edge("frontleft", "body", make_pose(Vec3(0.42, 0.04, 0.02), 0, 0, 0));
  edge("frontleft_fisheye", "frontleft", Pose::Identity());
  Camera cam;
  cam.name = "frontleft_fisheye";
  cam.width = 640, cam.height = 480;
  const auto rig = build_spot_rig({cam}, tree);
  ASSERT_EQ(rig->cameras().size(), 1u);
  EXPECT_NEAR(rig->camera_pose("body", 0).translation().x(), 0.42, 1e-12);
  const Pose footprint = rig->frames().lookup("body", kFootprintFrame);
  EXPECT_NEAR(footprint.translation().z(), -0.52, 1e-12);
  EXPECT_NEAR(footprint.translation().head<2>().norm(), 0, 1e-12) << "straight below the body";

  tree.erase("frontleft_fisheye");
  EXPECT_NE(error_of([&] { build_spot_rig({cam}, tree); }).find("'frontleft_fisheye' is not in the robot's frame tree"),
            std::string::npos);
}

TEST(SpotRig, PlaceholderHasTheStandardFramesAndEdgeNoiseIsIgnored) {
  const auto rig = placeholder_rig();
  for (const char* f : {"body", "vision", "odom", "gpe", "flat_body", "footprint"}) {
    EXPECT_TRUE(rig->frames().has_frame(f)) << f;
  }
  FrameEdge a{"vision", "body", Pose::Identity()};
  FrameEdge b = a;
  b.T_parent_child.translation().x() = 0.0005;
  EXPECT_FALSE(edge_moved(a, b));
  b.T_parent_child.translation().x() = 0.01;
  EXPECT_TRUE(edge_moved(a, b));
}

}  // namespace
}  // namespace omniview::spot
