// The Insta360/V4L2 adapter's parts without a device: format negotiation, finding a camera
// in sysfs, the capture clock, MJPEG streams and timestamps, TurboJPEG decoding with DCT
// scaling, the lens layout (split geometry) and the lens-circle check.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/camera/camera_model.h"
#include "insta360_adapter/decode/jpeg_decoder.h"
#include "insta360_adapter/decode/mjpeg_stream.h"
#include "insta360_adapter/device/capture_clock.h"
#include "insta360_adapter/device/device_locator.h"
#include "insta360_adapter/device/format_choice.h"
#include "insta360_adapter/device/v4l2_device.h"
#include "insta360_adapter/rig/lens_circle.h"
#include "insta360_adapter/rig/lens_layout.h"
#include "insta360_adapter/source/capture_config.h"
#include "tests/insta360/fake_air.h"

namespace omniview::insta360 {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

// ------------------------------------------------------------------ format negotiation

TEST(FormatChoice, TheAirsLargestDualFisheyeMjpeg) {
  FormatRequest r;
  r.aspect = 2;
  const auto f = choose_format(testing::air_formats(), r, "air");
  EXPECT_EQ(f.pixel_format, kMjpeg);
  EXPECT_EQ(f.width, 3008);
  EXPECT_EQ(f.height, 1504);
  EXPECT_EQ(f.fps, 30);
}

TEST(FormatChoice, ASizeAndRateTheConfigAsksFor) {
  FormatRequest r;
  r.width = 1920;
  r.height = 960;
  r.fps = 30;
  const auto f = choose_format(testing::air_formats(), r, "air");
  EXPECT_EQ(f.width, 1920);
  EXPECT_EQ(f.fps, 30);
}

TEST(FormatChoice, NoMatchListsWhatTheDeviceOffers) {
  FormatRequest r;
  r.width = 3840;
  r.height = 1920;
  try {
    choose_format(testing::air_formats(), r, "/dev/video2 (Insta360 Air)");
    FAIL() << "expected an error";
  } catch (const DeviceError& e) {
    EXPECT_EQ(e.fault(), DeviceFault::kNoFormat);
    const std::string m = e.what();
    EXPECT_NE(m.find("/dev/video2 (Insta360 Air) offers no MJPG 3840x1920"), std::string::npos) << m;
    EXPECT_NE(m.find("MJPG 3008x1504 @ 30/15 fps"), std::string::npos) << m;
    EXPECT_NE(m.find("MJPG 1472x736 @ 30 fps"), std::string::npos) << m;
  }
}

TEST(FormatChoice, YuyvWhenAllowedAndMjpegIsMissing) {
  const std::vector<FormatOption> webcam = {{kYuyv, 640, 480, {30}}, {kYuyv, 320, 240, {30}}};
  FormatRequest r;
  r.pixel_formats = {kMjpeg, kYuyv};
  EXPECT_EQ(choose_format(webcam, r, "cam").pixel_format, kYuyv);
  r.pixel_formats = {kMjpeg};
  EXPECT_THROW(choose_format(webcam, r, "cam"), DeviceError);
}

// ------------------------------------------------------------------ finding the camera

// A sysfs tree as Linux lays it out for a UVC camera: two nodes (capture, metadata) whose
// `device` links point into the USB device's folder.
struct FakeSysfs {
  fs::path root = fs::temp_directory_path() / ("omniview_sysfs_" + std::to_string(::getpid()));
  FakeSysfs() {
    fs::remove_all(root);
    add_camera("1-2", "2e1a", "1000", "AIR123", "Insta360 Air", {2, 3});
    add_camera("1-3", "046d", "0825", "", "UVC Camera (046d:0825)", {0, 1});
  }
  ~FakeSysfs() { fs::remove_all(root); }
  void add_camera(const std::string& port, const std::string& vid, const std::string& pid, const std::string& serial,
                  const std::string& name, std::vector<int> nodes) {
    const fs::path usb = root / "devices/usb1" / port;
    fs::create_directories(usb / (port + ":1.0"));
    std::ofstream(usb / "idVendor") << vid << "\n";
    std::ofstream(usb / "idProduct") << pid << "\n";
    if (!serial.empty()) std::ofstream(usb / "serial") << serial << "\n";
    for (size_t i = 0; i < nodes.size(); ++i) {
      const fs::path node = root / "class/video4linux" / ("video" + std::to_string(nodes[i]));
      fs::create_directories(node);
      std::ofstream(node / "name") << name << "\n";
      std::ofstream(node / "index") << i << "\n";
      fs::create_directory_symlink(usb / (port + ":1.0"), node / "device");
    }
  }
};

TEST(DeviceLocator, ByPathUsbIdsSerialAndName) {
  FakeSysfs sys;
  const std::string root = sys.root.string();
  EXPECT_EQ(find_video_node("/dev/video7", root), "/dev/video7");
  EXPECT_EQ(find_video_node("2e1a:1000", root), "/dev/video2");  // the capture node, not the metadata one
  EXPECT_EQ(find_video_node("usb:046D:0825", root), "/dev/video0");
  EXPECT_EQ(find_video_node("serial:AIR123", root), "/dev/video2");
  EXPECT_EQ(find_video_node("name:insta360", root), "/dev/video2");
  EXPECT_EQ(find_video_node("serial:NOPE", root), "");
  EXPECT_THROW(find_video_node("video2", root), std::invalid_argument);
  const std::string listed = describe_video_nodes(root);
  EXPECT_NE(listed.find("/dev/video2 'Insta360 Air' usb 2e1a:1000 serial AIR123"), std::string::npos) << listed;
  EXPECT_EQ(listed.find("/dev/video3"), std::string::npos) << "metadata nodes are not cameras: " << listed;
}

TEST(DeviceLocator, BusyDeviceHoldersFromProc) {
  // This process holds a file open: device_holders() of it from another pid's view is
  // tested through a fake /proc.
  const fs::path proc = fs::temp_directory_path() / ("omniview_proc_" + std::to_string(::getpid()));
  fs::remove_all(proc);
  fs::create_directories(proc / "4242/fd");
  std::ofstream(proc / "4242/comm") << "ffmpeg\n";
  const fs::path dev = proc / "video2";
  std::ofstream(dev) << "";
  fs::create_symlink(dev, proc / "4242/fd/3");
  EXPECT_EQ(device_holders(dev.string(), proc.string()), "held by pid 4242 (ffmpeg)");
  EXPECT_EQ(device_holders((proc / "other").string(), proc.string()), "");
  fs::remove_all(proc);
}

// ------------------------------------------------------------------ capture clock

TEST(CaptureClock, DriverTimestampsGoOnTheDaemonsClock) {
  CaptureClock clock;
  using Steady = std::chrono::steady_clock;
  const Steady::time_point now_steady(1000s);
  const auto now_system = std::chrono::system_clock::time_point(1'700'000'000s);
  // Captured 30 ms ago, dequeued 5 ms ago.
  const auto t = clock.to_system(std::chrono::nanoseconds(1000s - 30ms), now_steady - 5ms, now_steady, now_system);
  EXPECT_EQ(std::chrono::duration_cast<std::chrono::milliseconds>(now_system - t).count(), 30);
  EXPECT_EQ(clock.fallbacks(), 0u);
}

TEST(CaptureClock, ImplausibleStampsFallBackToTheDequeueTime) {
  CaptureClock clock;
  using Steady = std::chrono::steady_clock;
  const Steady::time_point now(1000s);
  const auto sys = std::chrono::system_clock::time_point(1'700'000'000s);
  for (const auto stamp : {0ns, std::chrono::nanoseconds(1001s), std::chrono::nanoseconds(990s)}) {  // none, future, 10 s old
    const auto t = clock.to_system(stamp, now - 5ms, now, sys);
    EXPECT_EQ(std::chrono::duration_cast<std::chrono::milliseconds>(sys - t).count(), 5);
  }
  EXPECT_EQ(clock.fallbacks(), 3u);
}

// ------------------------------------------------------------------ MJPEG and timestamps

TEST(MjpegStream, SplitsBackToBackFramesAndSkipsGarbage) {
  const auto a = testing::jpeg_of(testing::dual_fisheye_picture(64, 32));
  const auto b = testing::jpeg_of(testing::dual_fisheye_picture(64, 32, {2, 1}));
  std::vector<uint8_t> stream = {1, 2, 3};
  stream.insert(stream.end(), a.begin(), a.end());
  stream.insert(stream.end(), {0, 0, 0xFF});
  stream.insert(stream.end(), b.begin(), b.end());
  stream.insert(stream.end(), a.begin(), a.begin() + long(a.size() / 2));  // a truncated last frame
  const auto frames = split_mjpeg(stream.data(), stream.size());
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0], std::make_pair(size_t{3}, a.size()));
  EXPECT_EQ(frames[1].second, b.size());
  EXPECT_EQ(mjpeg_frame_problem(stream.data() + 3, a.size()), "");
  EXPECT_NE(mjpeg_frame_problem(a.data(), a.size() / 2).find("truncated"), std::string::npos);
  EXPECT_NE(mjpeg_frame_problem(a.data() + 1, a.size() - 1).find("start-of-image"), std::string::npos);
}

TEST(MjpegStream, TimestampFiles) {
  const auto t = parse_timestamps("# times\n100.0 a.jpg\n100.033 b.jpg  # second\n\n", "ts.txt");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[1].file, "b.jpg");
  EXPECT_DOUBLE_EQ(t[1].seconds, 100.033);
  EXPECT_THROW(parse_timestamps("1.0\n0.5\n", "ts.txt"), std::runtime_error);
  try {
    parse_timestamps("1.0\nabc\n", "ts.txt");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("ts.txt:2"), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------------ decoding

TEST(JpegDecoder, FullSizeBgrAndDctScaling) {
  const cv::Mat picture = testing::dual_fisheye_picture(752, 376);
  const auto jpeg = testing::jpeg_of(picture, 95);
  JpegDecoder d;
  const cv::Mat full = d.decode(jpeg.data(), jpeg.size());
  ASSERT_EQ(full.size(), picture.size());
  ASSERT_EQ(full.type(), CV_8UC3);
  EXPECT_TRUE(full.isContinuous());
  EXPECT_LT(cv::norm(full, picture, cv::NORM_L1) / full.total() / 3, 3.0) << "BGR order as the maps read it";
  for (int scale : {2, 4}) {
    const cv::Mat small = d.decode(jpeg.data(), jpeg.size(), scale);
    EXPECT_EQ(small.cols, 752 / scale);
    EXPECT_EQ(small.rows, 376 / scale);
    cv::Mat reference;
    cv::resize(picture, reference, small.size(), 0, 0, cv::INTER_AREA);
    EXPECT_LT(cv::norm(small, reference, cv::NORM_L1) / small.total() / 3, 6.0) << "scale 1/" << scale;
  }
}

TEST(JpegDecoder, CorruptAndTruncatedFramesAreErrors) {
  auto jpeg = testing::jpeg_of(testing::dual_fisheye_picture(256, 128));
  JpegDecoder d;
  std::vector<uint8_t> truncated(jpeg.begin(), jpeg.begin() + long(jpeg.size() / 2));
  EXPECT_THROW(d.decode(truncated.data(), truncated.size()), DecodeError);
  std::vector<uint8_t> garbage(1000, 0x42);
  EXPECT_THROW(d.decode(garbage.data(), garbage.size()), DecodeError);
  EXPECT_THROW(d.decode(jpeg.data(), 3), DecodeError);
}

// ------------------------------------------------------------------ split geometry

TEST(LensLayout, EachLensIsTheWholeFrameWithItsCropsOffset) {
  const Rig calibration = default_air_calibration();
  const auto crops = side_by_side(calibration);
  ASSERT_EQ(crops.size(), 2u);
  EXPECT_EQ(crops[1].rect, cv::Rect(1504, 0, 1504, 1504));
  const Rig rig = frame_rig(calibration, crops, {3008, 1504}, 1);
  ASSERT_EQ(rig.cameras().size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const Camera& lens = calibration.cameras()[i];
    const Camera& cam = rig.cameras()[i];
    EXPECT_EQ(cam.width, 3008);
    EXPECT_EQ(cam.height, 1504);
    // A ray lands where the lens image puts it, moved by the crop's origin.
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.3, -0.2, 1), Eigen::Vector3d(1, 0.5, -0.3)}) {
      Eigen::Vector2d in_lens, in_frame;
      ASSERT_TRUE(project(lens.model, p, in_lens));
      ASSERT_TRUE(project(cam.model, p, in_frame));
      EXPECT_NEAR(in_frame.x(), in_lens.x() + crops[i].rect.x, 1e-9);
      EXPECT_NEAR(in_frame.y(), in_lens.y(), 1e-9);
    }
    // Only its own half is usable.
    EXPECT_EQ(cam.mask.at<uint8_t>(752, 100 + int(i) * 1504), 255);
    EXPECT_EQ(cam.mask.at<uint8_t>(752, 100 + int(1 - i) * 1504), 0);
    EXPECT_TRUE(rig.camera_pose("insta360", i).isApprox(calibration.camera_pose("insta360", i)));
  }
}

TEST(LensLayout, HalfScaleIntrinsics) {
  const Rig calibration = default_air_calibration();
  const Rig full = frame_rig(calibration, side_by_side(calibration), {3008, 1504}, 1);
  const Rig half = frame_rig(calibration, side_by_side(calibration), {3008, 1504}, 2);
  EXPECT_EQ(half.cameras()[1].width, 1504);
  EXPECT_EQ(half.cameras()[1].height, 752);
  const Eigen::Vector3d p(0.2, 0.1, -0.4);  // behind the lens' plane: > 90 deg off axis
  Eigen::Vector2d a, b;
  ASSERT_TRUE(project(full.cameras()[1].model, p, a));
  ASSERT_TRUE(project(half.cameras()[1].model, p, b));
  EXPECT_NEAR(b.x(), (a.x() + 0.5) / 2 - 0.5, 1e-9);
  EXPECT_NEAR(b.y(), (a.y() + 0.5) / 2 - 0.5, 1e-9);
}

TEST(LensLayout, CropsThatDoNotFitAreNamed) {
  const Rig calibration = default_air_calibration();
  auto crops = side_by_side(calibration);
  EXPECT_THROW(check_crops(calibration, crops, {1920, 960}), std::invalid_argument);
  crops[0].camera = "left";
  try {
    check_crops(calibration, crops, {3008, 1504});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no camera 'left'"), std::string::npos);
  }
}

// ------------------------------------------------------------------ lens-circle check

TEST(LensCircle, FindsAnOffCentreLens) {
  // The second lens' disc sits 5 px right and 2 px up of the nominal centre.
  const cv::Mat frame = testing::dual_fisheye_picture(3008, 1504, {5, -2}, 733.0 / 752);
  const Rig calibration = default_air_calibration();
  const auto crops = side_by_side(calibration);
  const auto front = check_lens_circle(calibration.cameras()[0], frame, crops[0].rect);
  const auto back = check_lens_circle(calibration.cameras()[1], frame, crops[1].rect);
  ASSERT_TRUE(front.found);
  ASSERT_TRUE(back.found);
  EXPECT_LT(front.offset_px, 1.0) << describe(front);
  EXPECT_NEAR(back.circle_centre.x - back.principal_point.x, 5, 1.0) << describe(back);
  EXPECT_NEAR(back.circle_centre.y - back.principal_point.y, -2, 1.0) << describe(back);
  EXPECT_NEAR(back.radius_px, 733, 2) << describe(back);
  EXPECT_NEAR(back.expected_radius_px, 733, 1);
  // The same at half resolution (what a 1/2 DCT-scaled frame gives).
  cv::Mat small;
  cv::resize(frame, small, {1504, 752}, 0, 0, cv::INTER_AREA);
  const auto back_small = check_lens_circle(calibration.cameras()[1], small, {752, 0, 752, 752}, 2);
  ASSERT_TRUE(back_small.found);
  EXPECT_NEAR(back_small.circle_centre.x - back_small.principal_point.x, 5, 1.5) << describe(back_small);
}

TEST(LensCircle, NoneInTheDark) {
  const cv::Mat dark = cv::Mat::zeros(1504, 3008, CV_8UC3);
  const auto r = check_lens_circle(default_air_calibration().cameras()[0], dark, {0, 0, 1504, 1504});
  EXPECT_FALSE(r.found);
  EXPECT_NE(describe(r).find("no lens circle"), std::string::npos);
}

}  // namespace
}  // namespace omniview::insta360
