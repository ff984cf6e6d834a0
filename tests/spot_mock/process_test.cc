// The spot-mock program: command line, files it makes, the colour robot, shutdown.
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "bosdyn/api/image_service.grpc.pb.h"
#include "spot_adapter/mock/auth/certificates.h"
#include "tests/server/daemon_process.h"
#include "tests/spot_mock/mock_fixture.h"

namespace omniview::testing {
namespace {

using bosdyn::api::Image;

unsigned mode_of(const std::string& path) {
  struct stat st {};
  EXPECT_EQ(::stat(path.c_str(), &st), 0) << path;
  return st.st_mode & 0777;
}

TEST(SpotMockProgram, HelpDocumentsEveryFlag) {
  const auto help = run_process(std::string(SPOT_MOCK) + " --help");
  EXPECT_EQ(help.exit_code, 0);
  for (const char* flag : {"--port", "--bind", "--certs", "--credentials", "--token-lifetime-s", "--lockout-s", "--scene",
                           "--rgb", "--supersample", "--render-cache", "--ready-file", "--latency-ms", "--fail-probability",
                           "--image-error-probability", "--corrupt-probability", "--wrong-size-probability", "--away",
                           "control"}) {
    EXPECT_NE(help.output.find(flag), std::string::npos) << flag;
  }
  const auto control_help = run_process(std::string(SPOT_MOCK) + " control --help");
  EXPECT_EQ(control_help.exit_code, 0);
  for (const char* flag : {"--set", "--joint", "--expire-tokens", "--counters", "--reset-counters", "--faults"}) {
    EXPECT_NE(control_help.output.find(flag), std::string::npos) << flag;
  }
}

TEST(SpotMockProgram, BadArgumentsExitWithTwo) {
  // (Each run costs a process start with gRPC and OpenCV loaded: a few cases only.)
  EXPECT_EQ(run_process(std::string(SPOT_MOCK) + " --scene test --fail-probability 2").exit_code, 2);
  EXPECT_EQ(run_process(std::string(SPOT_MOCK) + " --frobnicate").exit_code, 2);
  EXPECT_EQ(run_process(std::string(SPOT_MOCK) + " control --counters").exit_code, 2) << "--port, --certs needed";
}

// The shared mock made its login and certificates: private where secret, and never printed.
TEST_F(SharedMockTest, MakesPrivateCredentialsAndCertificatesAndNeverLogsSecrets) {
  EXPECT_EQ(mode_of(mock().credentials_file()), 0600u);
  EXPECT_EQ(mock().username(), "user");
  EXPECT_TRUE(std::regex_match(mock().password(), std::regex("[A-Za-z0-9]{16}")));
  for (const auto& authority : spot_mock::mock_authorities()) {
    EXPECT_EQ(mode_of(spot_mock::key_file(mock().certs_dir(), authority)), 0600u) << authority;
    EXPECT_NE(mode_of(spot_mock::cert_file(mock().certs_dir(), authority)), 0u) << authority;
  }
  EXPECT_NE(mode_of(spot_mock::ca_cert_file(mock().certs_dir())), 0u);
  const std::string token = mock().login();
  const std::string log = mock().log();
  EXPECT_NE(log.find("spot-mock listening on " + mock().address() + " (certs in " + mock().certs_dir() + ")"),
            std::string::npos)
      << log;
  EXPECT_EQ(log.find(mock().password()), std::string::npos);
  EXPECT_EQ(log.find(token), std::string::npos);
}

// A colour robot with a login given beforehand, stopped with SIGTERM.
TEST(SpotMockProgram, ColourRobotOwnLoginAndCleanShutdown) {
  TempDir dir;
  dir.write("credentials.yaml", "username: alice\npassword: s3cret-enough\n");
  SpotMockProcess mock(dir.path(), {"--rgb", "--scene", "room", "--supersample", "1"});
  EXPECT_EQ(mock.username(), "alice");
  const std::string token = mock.login();
  auto stub = bosdyn::api::ImageService::NewStub(mock.channel("api.spot.robot"));

  bosdyn::api::ListImageSourcesResponse sources;
  ASSERT_TRUE(stub->ListImageSources(spot_context(token).get(), {}, &sources).ok());
  ASSERT_EQ(sources.image_sources_size(), 10) << "five cameras and their depth";
  EXPECT_EQ(sources.image_sources(0).pixel_formats(0), Image::PIXEL_FORMAT_RGB_U8);

  bosdyn::api::GetImageRequest request;
  for (auto pixels : {Image::PIXEL_FORMAT_UNKNOWN, Image::PIXEL_FORMAT_RGB_U8, Image::PIXEL_FORMAT_GREYSCALE_U8}) {
    auto* r = request.add_image_requests();
    r->set_image_source_name("left_fisheye_image");
    r->set_image_format(Image::FORMAT_RAW);
    r->set_pixel_format(pixels);
  }
  bosdyn::api::GetImageResponse response;
  ASSERT_TRUE(stub->GetImage(spot_context(token).get(), request, &response).ok());
  ASSERT_EQ(response.image_responses_size(), 3);
  const std::vector<std::pair<Image::PixelFormat, size_t>> expected = {
      {Image::PIXEL_FORMAT_RGB_U8, 640u * 480u * 3}, {Image::PIXEL_FORMAT_RGB_U8, 640u * 480u * 3},
      {Image::PIXEL_FORMAT_GREYSCALE_U8, 640u * 480u}};
  for (int i = 0; i < 3; ++i) {
    const auto& image = response.image_responses(i).shot().image();
    EXPECT_EQ(image.pixel_format(), expected[i].first) << i;
    EXPECT_EQ(image.data().size(), expected[i].second) << i;
  }
  EXPECT_EQ(mock.stop(SIGTERM), 0) << mock.log();
  EXPECT_NE(mock.log().find("shutting down"), std::string::npos);
}

// Every camera's raw greyscale picture (or, with `depth`, its depth image), as the mock serves it.
std::vector<std::string> raw_pictures(const SpotMockProcess& mock, bool depth = false) {
  auto stub = bosdyn::api::ImageService::NewStub(mock.channel("api.spot.robot"));
  const std::string token = mock.login();
  bosdyn::api::ListImageSourcesResponse sources;
  EXPECT_TRUE(stub->ListImageSources(spot_context(token).get(), {}, &sources).ok());
  bosdyn::api::GetImageRequest request;
  for (const auto& source : sources.image_sources()) {
    const bool depth_source = source.image_type() == bosdyn::api::ImageSource::IMAGE_TYPE_DEPTH;
    if (depth_source != depth) continue;
    auto* r = request.add_image_requests();
    r->set_image_source_name(source.name());
    r->set_image_format(Image::FORMAT_RAW);
    r->set_pixel_format(depth ? Image::PIXEL_FORMAT_DEPTH_U16 : Image::PIXEL_FORMAT_GREYSCALE_U8);
  }
  bosdyn::api::GetImageResponse response;
  EXPECT_TRUE(stub->GetImage(spot_context(token).get(), request, &response).ok());
  std::vector<std::string> pictures;
  for (const auto& r : response.image_responses()) pictures.push_back(r.shot().image().data());
  return pictures;
}

// --render-cache: a later start serves exactly the pictures and depth images a fresh render
// gave, and an entry that cannot be read is rendered again and replaced, never served.
TEST(SpotMockProgram, RenderCacheServesTheSamePicturesAndReplacesABrokenEntry) {
  TempDir dir;
  const std::filesystem::path cache = dir.path() / "render-cache";
  const std::vector<std::string> args = {"--scene", "test", "--supersample", "1", "--render-cache", cache.string()};
  std::vector<std::string> rendered;
  std::vector<std::string> depths;
  {
    SpotMockProcess mock(dir.path(), args);
    rendered = raw_pictures(mock);
    depths = raw_pictures(mock, true);
  }
  ASSERT_EQ(rendered.size(), 5u);
  for (const auto& picture : rendered) EXPECT_EQ(picture.size(), 640u * 480u);
  ASSERT_EQ(depths.size(), 5u);
  for (const auto& depth : depths) EXPECT_EQ(depth.size(), 640u * 480u * 2);

  // Two entries, the pictures' (PNG) and the depth images' (their wire bytes).
  std::filesystem::path pictures_entry, depth_entry;
  int entries = 0;
  for (const auto& item : std::filesystem::directory_iterator(cache)) {
    ++entries;
    (std::filesystem::exists(item.path() / "camera_0.png") ? pictures_entry : depth_entry) = item.path();
  }
  ASSERT_EQ(entries, 2) << "two entries, no staging folder left behind";
  ASSERT_TRUE(std::filesystem::exists(depth_entry / "camera_0.bin"));
  EXPECT_TRUE(std::filesystem::exists(pictures_entry / "key"));
  {
    SpotMockProcess mock(dir.path(), args);
    EXPECT_EQ(raw_pictures(mock), rendered) << "served from the cache";
    EXPECT_EQ(raw_pictures(mock, true), depths) << "served from the cache";
  }

  const auto broken = pictures_entry / "camera_2.png";
  std::ofstream(broken, std::ios::trunc) << "not a PNG";
  const auto lost = depth_entry / "camera_3.bin";
  std::filesystem::remove(lost);
  {
    SpotMockProcess mock(dir.path(), args);
    EXPECT_EQ(raw_pictures(mock), rendered) << "rendered again";
    EXPECT_EQ(raw_pictures(mock, true), depths) << "rendered again";
  }
  EXPECT_GT(std::filesystem::file_size(broken), 1000u) << "the broken entry was replaced";
  EXPECT_EQ(std::filesystem::file_size(lost), 640u * 480u * 2) << "the incomplete entry was replaced";
}

}  // namespace
}  // namespace omniview::testing
