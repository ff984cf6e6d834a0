// The `insta360` source against a fake Air (tests/insta360/fake_air.h): both lenses from
// one decoded frame, capture times on the daemon's clock, a busy device, unplugging and
// plugging back in mid-stream, a stalled stream, corrupt frames, DCT scaling that follows
// the views, nothing decoded while nobody watches, and the lens-circle check in status.
#include <gtest/gtest.h>

#include <condition_variable>
#include <cstdlib>
#include <fstream>
#include <mutex>

#include "insta360_adapter/source/capture_config.h"
#include "tests/insta360/fake_air.h"

namespace omniview::insta360 {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

double time_scale() {
  const char* s = std::getenv("OMNIVIEW_TEST_TIME_SCALE");
  return s ? std::max(1.0, std::atof(s)) : 1.0;
}

// Collects what the source delivers; waits on a condition variable (ThreadSanitizer sees it).
struct Sink {
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<std::shared_ptr<const FrameSet>> frames;

  Source::FrameCallback callback() {
    return [this](std::shared_ptr<const FrameSet> f) {
      std::lock_guard lock(mutex);
      frames.push_back(std::move(f));
      changed.notify_all();
    };
  }
  size_t count() {
    std::lock_guard lock(mutex);
    return frames.size();
  }
  std::shared_ptr<const FrameSet> last() {
    std::lock_guard lock(mutex);
    return frames.empty() ? nullptr : frames.back();
  }
  // Waits until `n` more frames than now arrived.
  bool wait_for_more(size_t n, std::chrono::milliseconds timeout = 15s) {
    std::unique_lock lock(mutex);
    const size_t target = frames.size() + n;
    return changed.wait_for(lock, timeout * time_scale(), [&] { return frames.size() >= target; });
  }
};

template <typename Pred>
bool eventually(Pred&& pred, std::chrono::milliseconds timeout = 15s) {
  const auto deadline = Clock::now() + timeout * time_scale();
  while (Clock::now() < deadline) {
    if (pred()) return true;
    std::this_thread::sleep_for(10ms);
  }
  return pred();
}

class AirSource : public ::testing::Test {
 protected:
  std::shared_ptr<testing::FakeAirState> air = std::make_shared<testing::FakeAirState>();
  Sink sink;
  std::unique_ptr<CaptureSource> source;

  void SetUp() override {
    air->jpeg = testing::jpeg_of(testing::dual_fisheye_picture(3008, 1504, {}, 733.0 / 752), 80);
    air->fps = 20;
  }
  void make(const std::string& extra_yaml = "") {
    const auto reader = YamlReader::from_string("name: air\ntype: insta360\n" + extra_yaml, "test.yaml");
    SourceConfig config{"air", &reader, reader.root(), "sources[0]", ""};
    CaptureSettings s = read_capture_settings(config, "insta360", testing::fake_air_opener(air));
    s.stall_timeout = 300ms;
    s.reopen_after = 1000ms;
    s.retry_every = 100ms;
    source = std::make_unique<CaptureSource>("air", std::move(s));
    source->start(sink.callback());
  }
  void TearDown() override {
    if (source) source->stop();
  }
  std::string message() { return source->health().message; }
};

TEST_F(AirSource, BothLensesShareOneDecodedFrame) {
  make();
  ASSERT_TRUE(sink.wait_for_more(3)) << "corrupt " << source->counters().corrupt_frames << ", sent " << air->sent
                                     << ", message " << message();
  const auto f = sink.last();
  ASSERT_EQ(f->images.size(), 2u);
  EXPECT_EQ(f->images[0].size(), cv::Size(3008, 1504));
  EXPECT_EQ(f->images[0].data, f->images[1].data) << "one decoded frame, no copies";
  EXPECT_TRUE(f->images[0].isContinuous());
  ASSERT_EQ(f->rig->cameras().size(), 2u);
  EXPECT_EQ(f->rig->cameras()[0].name, "front");
  EXPECT_EQ(f->rig->cameras()[1].width, 3008);
  ASSERT_EQ(f->encoded.size(), 2u);
  EXPECT_EQ(f->encoded[0].format, "jpeg");
  // The driver stamped the frame 8 ms before it was dequeued: the capture time says so.
  const auto age_at_arrival = std::chrono::system_clock::now() - f->capture_time - (Clock::now() - f->arrival);
  EXPECT_GE(age_at_arrival, 7ms);
  EXPECT_LT(age_at_arrival, 500ms);
  EXPECT_TRUE(source->health().connected);
  EXPECT_GT(f->sequence, 0u);
  EXPECT_EQ(source->rig()->cameras()[1].width, 3008);
}

TEST_F(AirSource, ABusyDeviceNamesItsHolderAndStreamsOnceFree) {
  air->busy = true;
  make();
  ASSERT_TRUE(eventually([&] { return message().find("busy") != std::string::npos; })) << message();
  EXPECT_NE(message().find("held by pid 4242 (ffmpeg)"), std::string::npos) << message();
  EXPECT_FALSE(source->health().connected);
  EXPECT_EQ(sink.count(), 0u);
  air->set([](auto& s) { s.busy = false; });
  ASSERT_TRUE(sink.wait_for_more(2));
  EXPECT_TRUE(source->health().connected);
  EXPECT_EQ(message(), "");
}

TEST_F(AirSource, UnpluggedMidStreamThenPluggedBackIn) {
  make();
  ASSERT_TRUE(sink.wait_for_more(2));
  air->set([](auto& s) { s.plugged = false; });
  ASSERT_TRUE(eventually([&] { return message().find("unplugged") != std::string::npos; })) << message();
  EXPECT_FALSE(source->health().connected);
  const int opens = air->opens;
  EXPECT_TRUE(eventually([&] { return air->opens > opens + 1; })) << "keeps looking for the camera";
  air->set([](auto& s) { s.plugged = true; });
  ASSERT_TRUE(sink.wait_for_more(2));
  EXPECT_TRUE(source->health().connected);
  EXPECT_EQ(message(), "");
  EXPECT_GE(source->counters().disconnects, 1u);
}

TEST_F(AirSource, AStalledStreamIsReportedAndReopened) {
  make();
  ASSERT_TRUE(sink.wait_for_more(2));
  air->set([](auto& s) { s.stalled = true; });
  ASSERT_TRUE(eventually([&] { return message().find("stalled") != std::string::npos; })) << message();
  const int opens = air->opens;
  ASSERT_TRUE(eventually([&] { return air->opens > opens; })) << "reopened after reopen_after";
  air->set([](auto& s) { s.stalled = false; });
  ASSERT_TRUE(sink.wait_for_more(2));
  EXPECT_TRUE(eventually([&] { return message().empty(); })) << message();
  EXPECT_GE(source->counters().stalls, 1u);
}

TEST_F(AirSource, CorruptFramesAreCountedAndSkipped) {
  make();
  ASSERT_TRUE(sink.wait_for_more(1));
  air->set([](auto& s) {
    s.corrupt_next = 3;
    s.truncate_instead = true;
  });
  ASSERT_TRUE(eventually([&] { return source->counters().corrupt_frames >= 3; }));
  air->set([](auto& s) {
    s.corrupt_next = 3;
    s.truncate_instead = false;
  });
  ASSERT_TRUE(eventually([&] {
    std::lock_guard lock(air->mutex);
    return air->corrupt_next == 0;
  }));
  ASSERT_TRUE(sink.wait_for_more(2)) << "good frames keep coming";
  EXPECT_GE(source->counters().corrupt_frames, 4u);  // scrambled data may still decode: some of them
  EXPECT_GE(source->health().errors, source->counters().corrupt_frames);
  EXPECT_TRUE(source->health().connected);
}

TEST_F(AirSource, DctScalingFollowsWhatTheViewsNeed) {
  make();
  ASSERT_TRUE(sink.wait_for_more(1));
  const uint64_t full_version = sink.last()->rig_version;
  // A 1024x512 panorama samples each lens about every 2.5 frame pixels.
  source->set_camera_sampling({2.5 / 3008, 2.5 / 3008});
  ASSERT_TRUE(eventually([&] { return sink.last()->images[0].cols == 1504; }));
  auto f = sink.last();
  EXPECT_EQ(f->images[0].size(), cv::Size(1504, 752));
  EXPECT_EQ(f->rig->cameras()[0].width, 1504);
  EXPECT_GT(f->rig_version, full_version);
  EXPECT_TRUE(f->encoded.empty()) << "the camera's JPEG is full size: not kept for a scaled rig";
  source->set_camera_sampling({5.0 / 3008, 0});
  ASSERT_TRUE(eventually([&] { return sink.last()->images[0].cols == 752; }));
  source->set_camera_sampling({0, 0});  // nobody watching: the scale stays
  ASSERT_TRUE(sink.wait_for_more(2));
  EXPECT_EQ(sink.last()->images[0].cols, 752);
  source->set_camera_sampling({1.0 / 3008, 2.5 / 3008});  // one view needs every pixel
  ASSERT_TRUE(eventually([&] { return sink.last()->images[0].cols == 3008; }));
  EXPECT_EQ(source->counters().decode_scale, 1);
}

TEST_F(AirSource, NothingIsDecodedWhileNobodyWatches) {
  make();
  source->set_wanted_cameras({false, false});
  const uint64_t sent = air->sent;
  ASSERT_TRUE(eventually([&] { return air->sent > sent + 4; }));
  const size_t delivered = sink.count();
  ASSERT_TRUE(eventually([&] { return air->sent > sent + 8; }));
  EXPECT_EQ(sink.count(), delivered);
  source->set_wanted_cameras({false, true});
  EXPECT_TRUE(sink.wait_for_more(2));
}

TEST_F(AirSource, TheLensCircleCheckReportsAnOffCentreLens) {
  air->jpeg = testing::jpeg_of(testing::dual_fisheye_picture(3008, 1504, {6, 0}, 733.0 / 752), 80);
  make();
  ASSERT_TRUE(eventually([&] { return source->counters().lens_circles.size() == 2; }));
  const auto circles = source->counters().lens_circles;
  EXPECT_LT(circles[0].offset_px, 1.5);
  EXPECT_NEAR(circles[1].offset_px, 6, 1.5);
  EXPECT_NE(message().find("calibration off: back: lens circle centre"), std::string::npos) << message();
  // The same, per camera, for ListCameras / `omniview cameras`.
  const auto checks = source->camera_checks();
  ASSERT_EQ(checks.size(), 2u);
  EXPECT_FALSE(checks[0].warning) << checks[0].summary;
  EXPECT_TRUE(checks[1].warning) << checks[1].summary;
  EXPECT_EQ(checks[1].camera, "back");
  EXPECT_EQ(checks[1].summary.rfind("lens circle centre", 0), 0u) << checks[1].summary;
}

TEST_F(AirSource, ConfigErrorsNameTheKey) {
  const auto reader = YamlReader::from_string("name: air\ntype: insta360\nlenses: {front: [0, 0, 1504, 1504], left: [1504, 0, 1504, 1504]}\n", "test.yaml");
  SourceConfig config{"air", &reader, reader.root(), "sources[0]", ""};
  try {
    read_capture_settings(config, "insta360", testing::fake_air_opener(air));
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("sources[0].lenses"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no camera 'left'"), std::string::npos) << e.what();
  }
  const auto bad_device = YamlReader::from_string("name: usb\ntype: v4l2\ndevice: video0\ncalibration: x.yaml\n", "test.yaml");
  SourceConfig c2{"usb", &bad_device, bad_device.root(), "sources[0]", ""};
  EXPECT_THROW(read_capture_settings(c2, "v4l2"), ConfigError);
}


// `type: v4l2`: a plain USB webcam that offers only YUYV, with a kalibr calibration.
TEST(V4l2Source, AYuyvWebcamWithAKalibrCalibration) {
  const std::string folder = ::testing::TempDir();
  std::ofstream(folder + "/camchain.yaml") << "cam0:\n  camera_model: pinhole\n  intrinsics: [50, 50, 31.5, 15.5]\n"
                                              "  distortion_model: radtan\n  distortion_coeffs: [0, 0, 0, 0]\n"
                                              "  resolution: [64, 32]\n";
  auto cam = std::make_shared<testing::FakeAirState>();
  cam->formats = {{kYuyv, 64, 32, {30}}, {kYuyv, 32, 16, {30}}};
  cam->jpeg.assign(64 * 32 * 2, 0);
  for (size_t i = 0; i < cam->jpeg.size(); i += 4) {  // Y U Y V: mid grey with a blue tint
    cam->jpeg[i] = 128;
    cam->jpeg[i + 1] = 160;
    cam->jpeg[i + 2] = 128;
    cam->jpeg[i + 3] = 128;
  }
  const auto reader = YamlReader::from_string("name: usb\ntype: v4l2\ncalibration: camchain.yaml\nmount: [0.2, 0, 0.5, 0, 0, 0]\n", "test.yaml");
  SourceConfig config{"usb", &reader, reader.root(), "sources[0]", folder};
  CaptureSource source("usb", read_capture_settings(config, "v4l2", testing::fake_air_opener(cam)));
  Sink sink;
  source.start(sink.callback());
  ASSERT_TRUE(sink.wait_for_more(2));
  const auto f = sink.last();
  ASSERT_EQ(f->images.size(), 1u);
  ASSERT_EQ(f->images[0].size(), cv::Size(64, 32));
  const cv::Vec3b px = f->images[0].at<cv::Vec3b>(10, 10);
  EXPECT_GT(px[0], px[2] + 20) << "U > 128 is blue, in BGR order";
  EXPECT_EQ(f->rig->cameras()[0].name, "cam0");
  // cam0 looks along the body's +x, and the body sits 0.2 m ahead of base_link.
  const Pose T = f->rig->camera_pose("base_link", 0);
  EXPECT_NEAR(T.translation().x(), 0.2, 1e-9);
  EXPECT_NEAR((T.linear() * Eigen::Vector3d::UnitZ()).x(), 1, 1e-9);
  source.stop();

  // Asking for MJPEG the camera does not have: the status lists what it offers.
  const auto mjpeg = YamlReader::from_string("name: usb\ntype: v4l2\ncalibration: camchain.yaml\nformat: {pixel_format: MJPG}\n", "test.yaml");
  SourceConfig c2{"usb", &mjpeg, mjpeg.root(), "sources[0]", folder};
  CaptureSource strict("usb", read_capture_settings(c2, "v4l2", testing::fake_air_opener(cam)));
  strict.start(sink.callback());
  ASSERT_TRUE(eventually([&] { return strict.health().message.find("offers no MJPG") != std::string::npos; }))
      << strict.health().message;
  EXPECT_NE(strict.health().message.find("YUYV 64x32 @ 30 fps"), std::string::npos) << strict.health().message;
  strict.stop();
}

// A unit's own kalibr camchain replaces the nominal calibration: cam0 is the left half and
// sits where the nominal front lens does; cam1 follows from T_cn_cnm1.
TEST(AirCalibration, AKalibrCamchainOverridesTheNominalOne) {
  const std::string folder = ::testing::TempDir();
  std::ofstream(folder + "/air_camchain.yaml")
      << "cam0:\n  camera_model: pinhole\n  intrinsics: [402, 401, 755.0, 749.0]\n"
         "  distortion_model: equidistant\n  distortion_coeffs: [0.01, 0, 0, 0]\n  resolution: [1504, 1504]\n"
         "cam1:\n  camera_model: pinhole\n  intrinsics: [399, 399, 748.0, 752.0]\n"
         "  distortion_model: equidistant\n  distortion_coeffs: [0.01, 0, 0, 0]\n  resolution: [1504, 1504]\n"
         "  T_cn_cnm1:\n  - [-1, 0, 0, 0]\n  - [0, 1, 0, 0]\n  - [0, 0, -1, -0.024]\n  - [0, 0, 0, 1]\n";
  const auto reader = YamlReader::from_string("name: air\ntype: insta360\ncalibration: air_camchain.yaml\n", "test.yaml");
  SourceConfig config{"air", &reader, reader.root(), "sources[0]", folder};
  auto air = std::make_shared<testing::FakeAirState>();
  const CaptureSettings s = read_capture_settings(config, "insta360", testing::fake_air_opener(air));
  ASSERT_EQ(s.crops.size(), 2u);
  EXPECT_EQ(s.crops[0].camera, "cam0");
  EXPECT_EQ(s.crops[1].rect, cv::Rect(1504, 0, 1504, 1504));
  EXPECT_EQ(s.frame_size, cv::Size(3008, 1504));
  const Rig nominal = default_air_calibration();
  EXPECT_TRUE(s.calibration->camera_pose("insta360", 0).isApprox(nominal.camera_pose("insta360", 0)));
  // cam1 looks the other way, 2.4 cm behind cam0's centre.
  const Pose back = s.calibration->camera_pose("insta360", 1);
  EXPECT_NEAR((back.linear() * Eigen::Vector3d::UnitZ()).x(), -1, 1e-9);
  EXPECT_NEAR(back.translation().x(), -0.012, 1e-9);
}

}  // namespace
}  // namespace omniview::insta360
