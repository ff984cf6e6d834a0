// The image service: sources, calibration and frame tree, pixels, formats and statuses.
#include <cmath>

#include <opencv2/core.hpp>

#include "bosdyn/api/image_service.grpc.pb.h"
#include "core/io/image_codec.h"
#include "spot_adapter/mock/world/mock_scene.h"
#include "tests/spot_mock/mock_fixture.h"

namespace omniview::testing {
namespace {

using bosdyn::api::Image;
using bosdyn::api::ImageResponse;
using spot_mock::mock_cameras;

bosdyn::api::ImageRequest image_request(const std::string& source, Image::Format format = Image::FORMAT_JPEG,
                                        Image::PixelFormat pixels = Image::PIXEL_FORMAT_UNKNOWN, double quality = 75) {
  bosdyn::api::ImageRequest r;
  r.set_image_source_name(source);
  r.set_image_format(format);
  r.set_pixel_format(pixels);
  r.set_quality_percent(quality);
  return r;
}

class SpotMockImages : public SharedMockTest {
 protected:
  void SetUp() override {
    SharedMockTest::SetUp();
    token_ = mock().login();
  }
  // `deadline`: a camera's first depth image is ray-cast on request (seconds under ASan).
  bosdyn::api::GetImageResponse get(const std::vector<bosdyn::api::ImageRequest>& requests,
                                    std::chrono::milliseconds deadline = std::chrono::seconds(10)) {
    bosdyn::api::GetImageRequest request;
    for (const auto& r : requests) *request.add_image_requests() = r;
    bosdyn::api::GetImageResponse response;
    const grpc::Status status = stub()->GetImage(spot_context(token_, deadline).get(), request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response;
  }
  std::unique_ptr<bosdyn::api::ImageService::Stub> stub() {
    return bosdyn::api::ImageService::NewStub(mock().channel("api.spot.robot"));
  }
  std::string token_;
};

// The camera's optical axes in the body frame.
Mat3 axes_in_body(const bosdyn::api::FrameTreeSnapshot& tree, const std::string& sensor) {
  return to_frame_graph(tree).lookup("body", sensor).linear();
}

TEST_F(SpotMockImages, FiveRotatedPinholesInSpotsFrameTree) {
  bosdyn::api::ListImageSourcesResponse response;
  ASSERT_TRUE(stub()->ListImageSources(spot_context(token_).get(), {}, &response).ok());
  EXPECT_EQ(response.header().error().code(), bosdyn::api::CommonError::CODE_OK);
  ASSERT_EQ(response.image_sources_size(), 10) << "five cameras, then their depth";
  for (int i = 5; i < 10; ++i) {
    const auto& d = response.image_sources(i);
    EXPECT_EQ(d.name(), mock_cameras()[i - 5].mount_frame + "_depth_in_visual_frame");
    EXPECT_EQ(d.image_type(), bosdyn::api::ImageSource::IMAGE_TYPE_DEPTH);
    EXPECT_EQ(d.depth_scale(), 1000);
    ASSERT_EQ(d.pixel_formats_size(), 1);
    EXPECT_EQ(d.pixel_formats(0), Image::PIXEL_FORMAT_DEPTH_U16);
    EXPECT_EQ(d.pinhole().DebugString(), response.image_sources(i - 5).pinhole().DebugString()) << "registered to it";
  }
  for (int i = 0; i < 5; ++i) {
    const auto& s = response.image_sources(i);
    EXPECT_EQ(s.name(), mock_cameras()[i].source);
    EXPECT_EQ(s.cols(), 640);
    EXPECT_EQ(s.rows(), 480);
    ASSERT_TRUE(s.has_pinhole()) << s.name();
    EXPECT_NEAR(s.pinhole().intrinsics().focal_length().x(), 330, 1e-9);
    EXPECT_NEAR(s.pinhole().intrinsics().focal_length().y(), 330, 1e-9);
    EXPECT_NEAR(s.pinhole().intrinsics().principal_point().x(), 319.5, 1e-9);
    EXPECT_NEAR(s.pinhole().intrinsics().principal_point().y(), 239.5, 1e-9);
    ASSERT_EQ(s.pixel_formats_size(), 1);
    EXPECT_EQ(s.pixel_formats(0), Image::PIXEL_FORMAT_GREYSCALE_U8);
  }
  const auto& tree = response.transforms_snapshot();
  const auto& edges = tree.child_to_parent_edge_map();
  ASSERT_TRUE(edges.count("body"));
  EXPECT_EQ(edges.at("body").parent_frame_name(), "");
  for (const char* frame : {"vision", "odom", "gpe", "flat_body"}) {
    ASSERT_TRUE(edges.count(frame)) << frame;
    EXPECT_EQ(edges.at(frame).parent_frame_name(), "body") << frame;
  }
  const Pose T_body_vision = to_frame_graph(tree).lookup("body", "vision");
  EXPECT_TRUE(T_body_vision.isApprox(Pose(Eigen::Translation3d(0, 0, -spot_mock::kBodyHeightM)), 1e-9));
  EXPECT_EQ(edges.at("frontleft_fisheye").parent_frame_name(), "frontleft") << "Spot's body -> mount -> sensor chain";

  // Optical z = viewing direction, y = image down. All look down; the front pair cross.
  const Mat3 fl = axes_in_body(tree, "frontleft_fisheye"), fr = axes_in_body(tree, "frontright_fisheye");
  const Mat3 left = axes_in_body(tree, "left_fisheye"), right = axes_in_body(tree, "right_fisheye");
  const Mat3 back = axes_in_body(tree, "back_fisheye");
  EXPECT_GT(fl(0, 2), 0.5);
  EXPECT_LT(fl(1, 2), -0.3) << "frontleft looks front-right";
  EXPECT_GT(fr(1, 2), 0.3) << "frontright looks front-left";
  EXPECT_GT(std::abs(fl(2, 0)), 0.7) << "front cameras are rolled about 90 deg: image x is near vertical";
  EXPECT_GT(left(1, 2), 0.8);
  EXPECT_LT(right(1, 2), -0.8);
  EXPECT_LT(back(0, 2), -0.8);
  EXPECT_GT(right(2, 1), 0.5) << "the right camera is upside down: image down points up";
  EXPECT_LT(left(2, 1), -0.5);
  for (const Mat3* cam : {&fl, &fr, &left, &right, &back}) {
    const double down_deg = std::asin(-(*cam)(2, 2)) * 180 / M_PI;
    EXPECT_GT(down_deg, 20);
    EXPECT_LT(down_deg, 35);
  }
}

// Recomputes pixels from what the wire says (intrinsics, frame tree) and the scene: the
// images, the calibration and the frame tree must agree exactly, as a daemon assumes.
TEST_F(SpotMockImages, RawPixelsAreTheSceneSeenThroughTheReportedCalibration) {
  const synthetic::Scene scene = spot_mock::make_scene(spot_mock::SceneKind::kTest);
  std::vector<bosdyn::api::ImageRequest> requests;
  for (const auto& cam : mock_cameras()) requests.push_back(image_request(cam.source, Image::FORMAT_RAW));
  const auto response = get(requests);
  ASSERT_EQ(response.image_responses_size(), 5);
  for (const auto& r : response.image_responses()) {
    ASSERT_EQ(r.status(), ImageResponse::STATUS_OK);
    const auto& image = r.shot().image();
    ASSERT_EQ(image.format(), Image::FORMAT_RAW);
    ASSERT_EQ(image.pixel_format(), Image::PIXEL_FORMAT_GREYSCALE_U8);
    ASSERT_EQ(image.cols(), 640);
    ASSERT_EQ(image.rows(), 480);
    ASSERT_EQ(image.data().size(), 640u * 480u);
    const auto& k = r.source().pinhole().intrinsics();
    const Pose T_vision_cam =
        to_frame_graph(r.shot().transforms_snapshot()).lookup("vision", r.shot().frame_name_image_sensor());
    size_t compared = 0, close = 0;
    double total = 0;
    for (int v = 4; v < 480; v += 16) {
      for (int u = 4; u < 640; u += 16) {
        const Vec3 ray((u - k.principal_point().x()) / k.focal_length().x(),
                       (v - k.principal_point().y()) / k.focal_length().y(), 1);
        const auto hit = scene.intersect(T_vision_cam.translation(), T_vision_cam.linear() * ray);
        if (!hit) continue;
        const Vec3 bgr = scene.colour(*hit);
        const double luma = 0.114 * bgr[0] + 0.587 * bgr[1] + 0.299 * bgr[2];
        const double d = std::abs(luma - static_cast<uint8_t>(image.data()[v * 640 + u]));
        ++compared;
        total += d;
        close += d <= 1.5;
      }
    }
    EXPECT_GT(compared, 500u) << r.source().name();
    EXPECT_LT(total / compared, 0.6) << r.source().name();
    EXPECT_GT(close, compared * 98 / 100) << r.source().name();  // a few straddle the wall's edge
  }
}

// A camera and its depth in one call, as a depth view asks: one acquisition time, the
// depth registered to the picture, and each depth pixel (mm along the optical axis) the
// scene's surface where the picture's ray meets it, up to the stereo range (4 m).
TEST_F(SpotMockImages, DepthInTheVisualFrameIsTheScenesDistanceAlongEachPixelsRay) {
  const synthetic::Scene scene = spot_mock::make_scene(spot_mock::SceneKind::kTest);
  const auto& cam = mock_cameras()[0];
  const auto response =
      get({image_request(cam.source, Image::FORMAT_RAW), image_request(cam.mount_frame + "_depth_in_visual_frame",
                                                                       Image::FORMAT_RAW, Image::PIXEL_FORMAT_DEPTH_U16)},
          std::chrono::seconds(60));
  ASSERT_EQ(response.image_responses_size(), 2);
  const auto& picture = response.image_responses(0);
  const auto& depth = response.image_responses(1);
  ASSERT_EQ(depth.status(), ImageResponse::STATUS_OK);
  EXPECT_EQ(depth.shot().acquisition_time().DebugString(), picture.shot().acquisition_time().DebugString());
  EXPECT_EQ(depth.shot().frame_name_image_sensor(), picture.shot().frame_name_image_sensor());
  const auto& image = depth.shot().image();
  ASSERT_EQ(image.pixel_format(), Image::PIXEL_FORMAT_DEPTH_U16);
  ASSERT_EQ(image.format(), Image::FORMAT_RAW);
  ASSERT_EQ(image.cols(), 640);
  ASSERT_EQ(image.rows(), 480);
  ASSERT_EQ(image.data().size(), 640u * 480u * 2);
  const auto& k = depth.source().pinhole().intrinsics();
  const double scale = depth.source().depth_scale();
  const Pose T_vision_cam =
      to_frame_graph(depth.shot().transforms_snapshot()).lookup("vision", depth.shot().frame_name_image_sensor());
  const auto* bytes = reinterpret_cast<const uint8_t*>(image.data().data());
  size_t measured = 0, agree = 0, beyond = 0;
  for (int v = 2; v < 480; v += 8) {
    for (int u = 2; u < 640; u += 8) {
      const size_t at = 2 * (static_cast<size_t>(v) * 640 + u);
      const double z = (bytes[at] | bytes[at + 1] << 8) / scale;  // little-endian
      const Vec3 ray((u - k.principal_point().x()) / k.focal_length().x(),
                     (v - k.principal_point().y()) / k.focal_length().y(), 1);
      const auto hit = scene.intersect(T_vision_cam.translation(), T_vision_cam.linear() * ray);
      const double truth = hit ? (T_vision_cam.inverse() * hit->point).z() : 0;
      if (z == 0) {
        beyond += !hit || truth > 3.99;
        continue;
      }
      ++measured;
      agree += std::abs(z - truth) <= 0.001;  // within the millimetre the format holds
    }
  }
  EXPECT_GT(measured, 1000u);
  EXPECT_EQ(agree, measured) << "depth pixels off the scene";
  EXPECT_GT(beyond, 0u) << "pixels beyond 4 m or of nothing read 0";

  // A depth source gives RAW DEPTH_U16 only, as Spot's do.
  const auto jpeg = get({image_request(cam.mount_frame + "_depth_in_visual_frame", Image::FORMAT_JPEG)});
  EXPECT_EQ(jpeg.image_responses(0).status(), ImageResponse::STATUS_UNSUPPORTED_IMAGE_FORMAT_REQUESTED);
  const auto grey = get({image_request(cam.mount_frame + "_depth_in_visual_frame", Image::FORMAT_RAW,
                                       Image::PIXEL_FORMAT_GREYSCALE_U8)});
  EXPECT_EQ(grey.image_responses(0).status(), ImageResponse::STATUS_UNSUPPORTED_PIXEL_FORMAT_REQUESTED);
}

TEST_F(SpotMockImages, JpegDecodesToTheSamePictureAtTheRequestedQuality) {
  const std::string source = mock_cameras()[0].source;
  const auto response = get({image_request(source, Image::FORMAT_RAW), image_request(source, Image::FORMAT_JPEG,
                                                                                      Image::PIXEL_FORMAT_UNKNOWN, 95),
                             image_request(source, Image::FORMAT_JPEG, Image::PIXEL_FORMAT_GREYSCALE_U8, 20),
                             image_request(source, Image::FORMAT_UNKNOWN)});
  ASSERT_EQ(response.image_responses_size(), 4);
  const std::string& raw_bytes = response.image_responses(0).shot().image().data();
  const cv::Mat raw(480, 640, CV_8UC1, const_cast<char*>(raw_bytes.data()));
  for (int i = 1; i < 4; ++i) {
    const auto& image = response.image_responses(i).shot().image();
    EXPECT_EQ(image.format(), Image::FORMAT_JPEG) << i;
    EXPECT_EQ(image.pixel_format(), Image::PIXEL_FORMAT_GREYSCALE_U8) << i;
    const cv::Mat jpeg = decode_image(image.data());
    ASSERT_EQ(jpeg.type(), CV_8UC1) << i;
    ASSERT_EQ(jpeg.size(), cv::Size(640, 480)) << i;
    EXPECT_GT(cv::PSNR(jpeg, raw), i == 2 ? 28 : 35) << i;
  }
  EXPECT_LT(response.image_responses(2).shot().image().data().size(),
            response.image_responses(1).shot().image().data().size() / 2)
      << "quality 20 is much smaller than quality 95";
}

TEST_F(SpotMockImages, StatusesFollowSpotsRulesInRequestOrder) {
  const std::string source = mock_cameras()[3].source;
  auto rgb_with_fallback = image_request(source, Image::FORMAT_RAW, Image::PIXEL_FORMAT_RGB_U8);
  rgb_with_fallback.add_fallback_formats(Image::PIXEL_FORMAT_GREYSCALE_U8);
  auto resized = image_request(source);
  resized.set_resize_ratio(0.5);
  auto unresized = image_request(source);
  unresized.set_resize_ratio(1.0);
  const auto response = get({image_request("hand_color_image"), image_request(source, Image::FORMAT_JPEG,
                                                                               Image::PIXEL_FORMAT_RGB_U8),
                             rgb_with_fallback, resized, image_request(source, Image::FORMAT_RLE),
                             image_request(source, Image::FORMAT_JPEG, Image::PIXEL_FORMAT_DEPTH_U16), unresized});
  const std::vector<ImageResponse::Status> expected = {
      ImageResponse::STATUS_UNKNOWN_CAMERA,
      ImageResponse::STATUS_UNSUPPORTED_PIXEL_FORMAT_REQUESTED,
      ImageResponse::STATUS_OK,
      ImageResponse::STATUS_UNSUPPORTED_RESIZE_RATIO_REQUESTED,
      ImageResponse::STATUS_UNSUPPORTED_IMAGE_FORMAT_REQUESTED,
      ImageResponse::STATUS_UNSUPPORTED_PIXEL_FORMAT_REQUESTED,
      ImageResponse::STATUS_OK,
  };
  ASSERT_EQ(response.image_responses_size(), static_cast<int>(expected.size()));
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(response.image_responses(i).status(), expected[i]) << "request " << i;
  }
  const auto& fallback = response.image_responses(2).shot().image();
  EXPECT_EQ(fallback.pixel_format(), Image::PIXEL_FORMAT_GREYSCALE_U8);
  EXPECT_EQ(fallback.data().size(), 640u * 480u);
  EXPECT_EQ(response.image_responses(1).source().name(), source) << "the source is described even when refused";
}

TEST_F(SpotMockImages, TooManyRequestsInOneCallIsAnInvalidRequest) {
  const auto response = get(std::vector<bosdyn::api::ImageRequest>(65, image_request(mock_cameras()[0].source)));
  EXPECT_EQ(response.header().error().code(), bosdyn::api::CommonError::CODE_INVALID_REQUEST);
  EXPECT_EQ(response.image_responses_size(), 0);
}

TEST_F(SpotMockImages, ShotsCarryTimeFrameAndTree) {
  const auto before = std::chrono::system_clock::now();
  const auto response = get({image_request(mock_cameras()[0].source), image_request(mock_cameras()[4].source)});
  ASSERT_EQ(response.image_responses_size(), 2);
  const auto& a = response.image_responses(0).shot();
  const auto& b = response.image_responses(1).shot();
  EXPECT_EQ(a.frame_name_image_sensor(), "frontleft_fisheye");
  EXPECT_EQ(b.frame_name_image_sensor(), "back_fisheye");
  EXPECT_EQ(a.acquisition_time().seconds(), b.acquisition_time().seconds()) << "hardware-synchronised";
  EXPECT_EQ(a.acquisition_time().nanos(), b.acquisition_time().nanos());
  const double acquired = a.acquisition_time().seconds() + a.acquisition_time().nanos() * 1e-9;
  EXPECT_NEAR(acquired, std::chrono::duration<double>(before.time_since_epoch()).count(), 5);
  EXPECT_TRUE(a.transforms_snapshot().child_to_parent_edge_map().count("frontleft_fisheye"));
  EXPECT_TRUE(response.image_responses(0).source().has_pinhole());
}

TEST_F(SpotMockImages, CountersCountCallsAndRequestsPerSource) {
  counters(true);
  const std::string fl = mock_cameras()[0].source, back = mock_cameras()[4].source;
  get({image_request(fl), image_request(back)});
  get({image_request(fl), image_request("no_such_camera")});
  const auto c = counters();
  EXPECT_EQ(c.get_image_calls(), 2u);
  EXPECT_EQ(c.image_requests_by_source().at(fl), 2u);
  EXPECT_EQ(c.image_requests_by_source().at(back), 1u);
  EXPECT_EQ(c.image_requests_by_source().at("no_such_camera"), 1u);
  EXPECT_EQ(c.image_requests_by_source().size(), 3u);
}

}  // namespace
}  // namespace omniview::testing
