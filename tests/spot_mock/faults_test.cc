// Fault injection through the control service and the `spot-mock control` command.
#include "bosdyn/api/image_service.grpc.pb.h"
#include "bosdyn/api/robot_id_service.grpc.pb.h"
#include "core/io/image_codec.h"
#include "tests/spot_mock/mock_fixture.h"

namespace omniview::testing {
namespace {

using bosdyn::api::Image;
using bosdyn::api::ImageResponse;

class SpotMockFaults : public SharedMockTest {
 protected:
  grpc::Status get_image(Image::Format format, bosdyn::api::GetImageResponse* response) {
    bosdyn::api::GetImageRequest request;
    for (const char* source : {"frontleft_fisheye_image", "back_fisheye_image"}) {
      auto* r = request.add_image_requests();
      r->set_image_source_name(source);
      r->set_image_format(format);
    }
    return bosdyn::api::ImageService::NewStub(mock().channel("api.spot.robot"))
        ->GetImage(spot_context(mock().login()).get(), request, response);
  }
  grpc::Status robot_id() {
    bosdyn::api::RobotIdResponse response;
    return bosdyn::api::RobotIdService::NewStub(mock().channel("id.spot.robot"))
        ->GetRobotId(spot_context().get(), {}, &response);
  }
};

TEST_F(SpotMockFaults, LatencyDelaysEveryCall) {
  ASSERT_TRUE(robot_id().ok());  // connected, so the handshake is not timed
  spotmock::v1::Faults f;
  f.set_latency_ms(300);
  EXPECT_EQ(set_faults(f).latency_ms(), 300u);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(robot_id().ok());
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(300));
}

TEST_F(SpotMockFaults, AwayFailsEveryCallUntilCleared) {
  spotmock::v1::Faults f;
  f.set_away(true);
  set_faults(f);
  const grpc::Status away = robot_id();
  EXPECT_EQ(away.error_code(), grpc::StatusCode::UNAVAILABLE);
  f.set_away(false);
  set_faults(f);
  EXPECT_TRUE(robot_id().ok());
}

TEST_F(SpotMockFaults, FailedGetImageIsAGrpcErrorOrAHeaderError) {
  spotmock::v1::Faults f;
  f.set_fail_probability(1);
  set_faults(f);
  int grpc_errors = 0, header_errors = 0;
  for (int i = 0; i < 12; ++i) {
    bosdyn::api::GetImageResponse response;
    const grpc::Status status = get_image(Image::FORMAT_JPEG, &response);
    if (!status.ok()) {
      EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAVAILABLE);
      ++grpc_errors;
    } else {
      EXPECT_EQ(response.header().error().code(), bosdyn::api::CommonError::CODE_INTERNAL_SERVER_ERROR);
      EXPECT_EQ(response.image_responses_size(), 0);
      ++header_errors;
    }
  }
  EXPECT_EQ(grpc_errors + header_errors, 12);
  EXPECT_GT(grpc_errors, 0) << "both kinds appear (each with probability 1/2; 12 tries)";
  EXPECT_GT(header_errors, 0);
}

TEST_F(SpotMockFaults, ImageErrorsCorruptionAndWrongSizesPerImage) {
  bosdyn::api::GetImageResponse clean;
  ASSERT_TRUE(get_image(Image::FORMAT_JPEG, &clean).ok());

  spotmock::v1::Faults f;
  f.set_image_error_probability(1);
  set_faults(f);
  bosdyn::api::GetImageResponse response;
  ASSERT_TRUE(get_image(Image::FORMAT_JPEG, &response).ok());
  for (const auto& r : response.image_responses()) EXPECT_EQ(r.status(), ImageResponse::STATUS_IMAGE_DATA_ERROR);

  f.set_image_error_probability(0);
  f.set_corrupt_probability(1);
  set_faults(f);
  ASSERT_TRUE(get_image(Image::FORMAT_JPEG, &response).ok());
  for (int i = 0; i < 2; ++i) {
    const std::string& bytes = response.image_responses(i).shot().image().data();
    EXPECT_EQ(response.image_responses(i).status(), ImageResponse::STATUS_OK);
    EXPECT_NE(bytes, clean.image_responses(i).shot().image().data());
    const cv::Mat decoded = decode_image(bytes);
    EXPECT_TRUE(decoded.empty() || bytes.size() < clean.image_responses(i).shot().image().data().size())
        << "garbled from the start, or cut short";
  }

  f.set_corrupt_probability(0);
  f.set_wrong_size_probability(1);
  set_faults(f);
  ASSERT_TRUE(get_image(Image::FORMAT_RAW, &response).ok());
  for (const auto& r : response.image_responses()) {
    const auto& image = r.shot().image();
    EXPECT_NE(static_cast<size_t>(image.cols()) * image.rows(), image.data().size());
  }
}

TEST_F(SpotMockFaults, ControlCommandSetsFaultsAndPrintsCounters) {
  counters(true);
  auto out = mock().control("--set latency_ms=20 --set away=false --set corrupt_probability=0.25");
  EXPECT_EQ(out.exit_code, 0) << out.text;
  EXPECT_NE(out.text.find("latency_ms=20\n"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find("corrupt_probability=0.25\n"), std::string::npos) << out.text;

  bosdyn::api::GetImageResponse response;
  ASSERT_TRUE(get_image(Image::FORMAT_JPEG, &response).ok());
  out = mock().control("--counters --reset-counters");
  EXPECT_EQ(out.exit_code, 0) << out.text;
  EXPECT_NE(out.text.find("get_image_calls=1\n"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find("logins_ok=1\n"), std::string::npos) << out.text;
  EXPECT_NE(out.text.find("image_requests.frontleft_fisheye_image=1\n"), std::string::npos) << out.text;
  EXPECT_EQ(counters().get_image_calls(), 0u) << "reset";

  EXPECT_EQ(mock().control("--set fail_probability=1.5 --joint xx.kn=1").exit_code, 1) << "the mock refuses them";
}

}  // namespace
}  // namespace omniview::testing
