// The done-when test of the Insta360 Air adapter: the real omniviewd with
// config/insta360.yaml as shipped, playing the bundled sample recording through the
// `insta360` source's file form, serves a 360 deg panorama of the synthetic room the sample
// was rendered in, equal to the room ray-cast from the panorama's own centre (PSNR, the
// golden tests' measure), a PTZ view steered with the real CLI, and its status, through the
// same API and CLI as a Spot.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <opencv2/imgproc.hpp>

#include "core/io/image_codec.h"
#include "core/synthetic/render.h"
#include "core/view/view.h"
#include "server/config/daemon_config.h"
#include "tests/server/daemon_process.h"

namespace omniview::testing {
namespace {

const std::string kConfig = std::string(OMNIVIEW_SOURCE_DIR) + "/config/insta360.yaml";

// config/insta360.yaml as shipped, on a free port, its relative paths made absolute.
std::string shipped_config_text() {
  std::ifstream in(kConfig);
  std::stringstream s;
  s << in.rdbuf();
  std::string text = s.str();
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    if (at == std::string::npos) throw std::runtime_error("config/insta360.yaml has no '" + from + "'");
    text.replace(at, from.size(), to);
  };
  replace("listen: 127.0.0.1:50051", "listen: 127.0.0.1:0");
  std::string sample = OMNIVIEW_SOURCE_DIR;
  sample += "/config/insta360/sample";
  replace("file: insta360/sample", "file: " + sample);
  return text;
}

grpc::Status snapshot(v1::Omniview::Stub& stub, const std::string& view, v1::Frame& frame) {
  v1::SnapshotRequest r;
  r.set_view(view);
  r.set_encoding(v1::RAW);
  r.set_timeout_ms(int(8000 * test_time_scale()));
  return stub.GetSnapshot(make_context("", std::chrono::milliseconds(int(10000 * test_time_scale()))).get(), r, &frame);
}

// What an ideal camera at the view's centre sees of `scene`: each pixel's ray cast into it,
// 2 x 2 rays per pixel averaged (the sample was rendered supersampled too). `valid`: 255
// where the view has a ray at all.
cv::Mat ray_cast_view(const synthetic::Scene& scene, const View& view, const Pose& T_world_view, cv::Mat& valid) {
  cv::Mat out(view.height(), view.width(), CV_8UC3, cv::Scalar::all(0));
  valid = cv::Mat::zeros(view.height(), view.width(), CV_8UC1);
  const Vec3 origin = T_world_view.translation();
  for (int y = 0; y < view.height(); ++y) {
    for (int x = 0; x < view.width(); ++x) {
      Vec3 sum = Vec3::Zero();
      int n = 0;
      for (double dy : {-0.25, 0.25}) {
        for (double dx : {-0.25, 0.25}) {
          Vec3 dir;
          if (!view.pixel_to_direction(x + dx, y + dy, dir)) continue;
          const auto hit = scene.intersect(origin, T_world_view.rotation() * dir);
          if (!hit) continue;
          sum += scene.colour(*hit);
          ++n;
        }
      }
      if (n == 0) continue;
      valid.at<uint8_t>(y, x) = 255;
      const Vec3 c = sum / n;
      out.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<uint8_t>(c.x()), cv::saturate_cast<uint8_t>(c.y()),
                                          cv::saturate_cast<uint8_t>(c.z()));
    }
  }
  return out;
}

cv::Mat bgr_of(const v1::Frame& f) {
  cv::Mat rgb(f.height(), f.width(), CV_8UC3, const_cast<char*>(f.data().data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

// One daemon for the suite: starting it (three maps over a 4.5 MP dual fisheye, built
// again once the panorama's 1/2 DCT scale is chosen) is the slow part under the sanitizers.
class AirDaemon : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    shared_dir = new TempDir;
    shared_daemon = new DaemonProcess(*shared_dir, shipped_config_text());
  }
  static void TearDownTestSuite() {
    delete shared_daemon;
    delete shared_dir;
    shared_daemon = nullptr;
    shared_dir = nullptr;
  }
  static inline TempDir* shared_dir = nullptr;
  static inline DaemonProcess* shared_daemon = nullptr;

  const TempDir& dir = *shared_dir;
  DaemonProcess& daemon = *shared_daemon;
  DaemonConfig config = load_daemon_config(kConfig);
  std::unique_ptr<v1::Omniview::Stub> stub = make_stub(daemon.address());

  const ViewSpec& view(const std::string& name) {
    for (const auto& v : config.views) {
      if (v.name == name) return v;
    }
    throw std::runtime_error("no view " + name);
  }
};

TEST_F(AirDaemon, ServesThePanoramaOfTheSceneSeamlessly) {
  v1::Frame frame;
  const auto status = snapshot(*stub, "panorama", frame);
  ASSERT_TRUE(status.ok()) << status.error_message() << "\n" << daemon.log();
  const cv::Mat image = bgr_of(frame);
  ASSERT_EQ(image.size(), cv::Size(1024, 512));

  // The truth: the room the sample was rendered in, seen from the view's centre (the camera
  // body 1 m above base_link, the room's floor: config/insta360.yaml's mount).
  const ViewSpec& spec = view("panorama");
  const auto v = View::create(spec);
  const Pose T_base_body = make_pose(Vec3(0, 0, 1.0), 0, 0, 0);
  cv::Mat on_surface;
  const cv::Mat truth = ray_cast_view(synthetic::Scene::room(), *v, T_base_body * spec.T_frame_view(), on_surface);
  double sq = 0;
  size_t n = 0, covered = 0, surface = 0;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      if (!on_surface.at<uint8_t>(y, x)) continue;
      ++surface;
      const cv::Vec3b a = image.at<cv::Vec3b>(y, x), b = truth.at<cv::Vec3b>(y, x);
      if (a == cv::Vec3b(0, 0, 0)) continue;
      ++covered;
      for (int c = 0; c < 3; ++c) sq += std::pow(double(a[c]) - b[c], 2);
      n += 3;
    }
  }
  const double psnr = 10 * std::log10(255.0 * 255.0 / (sq / std::max<size_t>(n, 1)));
  std::cout << "Air panorama vs scene truth: " << psnr << " dB over " << covered << " of " << surface << " pixels\n";
  EXPECT_GT(double(covered) / surface, 0.99) << "the two 210 deg lenses cover the whole sphere";
  EXPECT_GE(psnr, 30.0);
  if (psnr < 30.0 || HasFailure()) {
    write_image(dir.path() / "panorama.png", image);
    write_image(dir.path() / "truth.png", truth);
  }

  // The seam: the columns where the panorama passes from one lens to the other (+-90 deg
  // azimuth) are as good as the rest.
  double seam_sq = 0;
  size_t seam_n = 0;
  for (int x : {255, 256, 767, 768}) {
    for (int y = 64; y < 448; ++y) {
      const cv::Vec3b a = image.at<cv::Vec3b>(y, x), b = truth.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) seam_sq += std::pow(double(a[c]) - b[c], 2);
      seam_n += 3;
    }
  }
  const double seam_psnr = 10 * std::log10(255.0 * 255.0 / (seam_sq / seam_n));
  std::cout << "at the seams: " << seam_psnr << " dB\n";
  EXPECT_GE(seam_psnr, 30.0);
}

TEST_F(AirDaemon, APtzViewSteeredWithTheCli) {
  v1::Frame before;
  ASSERT_TRUE(snapshot(*stub, "ptz", before).ok()) << daemon.log();
  const std::string cli = std::string(OMNIVIEW_CLI) + " --server " + daemon.address();
  const auto ptz = run_process(cli + " ptz ptz --dpan 90");
  ASSERT_EQ(ptz.exit_code, 0) << ptz.output;
  const auto shot = run_process(cli + " snapshot ptz -o " + (dir.path() / "ptz.png").string());
  ASSERT_EQ(shot.exit_code, 0) << shot.output;
  const cv::Mat after = read_image(dir.path() / "ptz.png", ImageColour::kBgr);
  ASSERT_EQ(after.size(), cv::Size(640, 480));
  cv::Mat grey;
  cv::cvtColor(after, grey, cv::COLOR_BGR2GRAY);
  EXPECT_GT(cv::countNonZero(grey) / double(grey.total()), 0.99) << "the lenses see every direction";
  cv::Mat diff;
  cv::absdiff(bgr_of(before), after, diff);
  EXPECT_GT(cv::mean(diff)[0] + cv::mean(diff)[1] + cv::mean(diff)[2], 20) << "panned 90 deg: another part of the scene";
}

TEST_F(AirDaemon, StatusAndCamerasLikeAnyOtherSource) {
  v1::Frame frame;
  ASSERT_TRUE(snapshot(*stub, "front", frame).ok()) << daemon.log();
  const auto status = run_process(std::string(OMNIVIEW_CLI) + " status --server " + daemon.address());
  ASSERT_EQ(status.exit_code, 0) << status.output;
  EXPECT_NE(status.output.find("air"), std::string::npos) << status.output;
  EXPECT_NE(status.output.find("insta360"), std::string::npos) << status.output;
  const auto cameras = run_process(std::string(OMNIVIEW_CLI) + " cameras --server " + daemon.address());
  ASSERT_EQ(cameras.exit_code, 0) << cameras.output;
  EXPECT_NE(cameras.output.find("front"), std::string::npos) << cameras.output;
  EXPECT_NE(cameras.output.find("back"), std::string::npos) << cameras.output;
  // The lens-circle check per camera: the sample's lenses sit where the calibration says.
  EXPECT_NE(cameras.output.find("calibration check: front: lens circle centre"), std::string::npos) << cameras.output;
  EXPECT_NE(cameras.output.find("calibration check: back: lens circle centre"), std::string::npos) << cameras.output;
  EXPECT_EQ(cameras.output.find("calibration off"), std::string::npos) << cameras.output;
  v1::ListCamerasResponse listed;
  grpc::ClientContext list_context;
  ASSERT_TRUE(stub->ListCameras(&list_context, v1::ListCamerasRequest(), &listed).ok());
  ASSERT_EQ(listed.cameras_size(), 2);
  for (const auto& c : listed.cameras()) {
    EXPECT_FALSE(c.calibration_warning()) << c.name() << ": " << c.calibration_check();
    EXPECT_NE(c.calibration_check().find(" px from the principal point"), std::string::npos) << c.calibration_check();
    // Each lens is half of the shared frame, its axis off the frame's centre: its field is
    // measured through the axis, a 210 deg fisheye both ways (it read 105 x 0).
    EXPECT_NEAR(c.hfov_deg(), 210, 3) << c.name();
    EXPECT_NEAR(c.vfov_deg(), 210, 3) << c.name();
  }
  // No warning in the status either.
  v1::Status s;
  ASSERT_TRUE(stub->GetStatus(make_context().get(), v1::GetStatusRequest(), &s).ok());
  ASSERT_EQ(s.sources_size(), 1);
  EXPECT_TRUE(s.sources(0).connected());
  EXPECT_EQ(s.sources(0).message().find("calibration off"), std::string::npos) << s.sources(0).message();
}

}  // namespace
}  // namespace omniview::testing
