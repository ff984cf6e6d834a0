// omniviewd's `spot` source against spot-mock, both real processes on loopback ports, the
// way a robot deployment runs: login, discovery, the default views of config/spot.yaml,
// pulling only watched cameras, wrong passwords, a robot that goes away and comes back,
// bad images, and credentials that never reach a log.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>

#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include "core/synthetic/render.h"
#include "core/view/view.h"
#include "core/view/view_yaml.h"
#include "spot_adapter/mock/world/mock_scene.h"
#include "tests/server/daemon_process.h"
#include "tests/spot_mock/spot_mock_process.h"

namespace omniview::testing {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// spot-mock on `port` in the test's folder, by default with the test scene rendered with
// one ray per pixel (a third of the start-up time, which matters under the sanitizers).
class SpotMock : public SpotMockProcess {
 public:
  SpotMock(const TempDir& dir, int port, const std::string& scene = "test", std::vector<std::string> extra = {})
      : SpotMockProcess(dir.path(), with_defaults(scene, std::move(extra)), port) {}

  static std::string certs(const TempDir& dir) { return certs_dir(dir.path()); }
  static std::string credentials(const TempDir& dir) { return (dir.path() / "credentials.yaml").string(); }

 private:
  static std::vector<std::string> with_defaults(const std::string& scene, std::vector<std::string> extra) {
    extra.insert(extra.end(), {"--scene", scene});
    if (std::find(extra.begin(), extra.end(), "--supersample") == extra.end()) {
      extra.insert(extra.end(), {"--supersample", "1"});
    }
    return extra;
  }
};

// `spot-mock control ARGS`: its KEY=VALUE lines, as a map.
std::map<std::string, double> mock_control(const SpotMockProcess& mock, const std::string& args) {
  const auto r = mock.control(args);
  EXPECT_EQ(r.exit_code, 0) << r.text;
  std::map<std::string, double> out;
  std::istringstream lines(r.text);
  for (std::string line; std::getline(lines, line);) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    try {
      out[line.substr(0, eq)] = std::stod(line.substr(eq + 1));
    } catch (const std::exception&) {
    }
  }
  return out;
}

// The views and robot model of the shipped config/spot.yaml, as YAML to append to a test
// config (paths made absolute: the test's config lives elsewhere).
std::string shipped_views() {
  const std::string folder = std::string(OMNIVIEW_SOURCE_DIR) + "/config/";
  YAML::Node config = YAML::LoadFile(folder + "spot.yaml");
  YAML::Node models = config["robot_models"];
  for (auto m : models) {
    m["urdf"] = folder + m["urdf"].as<std::string>();
    m.remove("mesh_path");
  }
  YAML::Emitter e;
  e << YAML::BeginMap << YAML::Key << "views" << YAML::Value << config["views"] << YAML::Key << "robot_models"
    << YAML::Value << models << YAML::EndMap;
  return std::string(e.c_str()) + "\n";
}

std::string daemon_config(const TempDir& dir, int mock_port, const std::string& credentials,
                          const std::string& extra = shipped_views(), const std::string& source_keys = "") {
  std::ostringstream s;
  s << "listen: 127.0.0.1:0\n"
    << "sources:\n"
    << "  - name: spot\n"
    << "    type: spot\n"
    << "    robot: 127.0.0.1:" << mock_port << "\n"
    << "    ca_file: " << SpotMock::certs(dir) << "/ca.pem\n"
    << "    credentials_file: " << credentials << "\n"
    << "    rate_hz: 15\n"
    << source_keys << extra;
  return s.str();
}

v1::SourceStatus source_status(v1::Omniview::Stub& stub) {
  v1::Status st;
  EXPECT_TRUE(stub.GetStatus(make_context().get(), v1::GetStatusRequest(), &st).ok());
  for (const auto& s : st.sources()) {
    if (s.name() == "spot") return s;
  }
  ADD_FAILURE() << "no source 'spot' in status";
  return {};
}

// Polls `done` every 50 ms until it holds or `timeout` passes.
template <typename F>
bool eventually(F&& done, std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  while (Clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(50ms);
  }
  return done();
}

// The timeout is 8 s in the release run, times the sanitizer time scale otherwise (the mock
// renders and the daemon builds its maps several times slower there).
grpc::Status snapshot(v1::Omniview::Stub& stub, const std::string& view, v1::Frame& frame, int timeout_ms = 8000) {
  timeout_ms = static_cast<int>(timeout_ms * test_time_scale());
  v1::SnapshotRequest r;
  r.set_view(view);
  r.set_encoding(v1::RAW);
  r.set_timeout_ms(timeout_ms);
  return stub.GetSnapshot(make_context("", std::chrono::milliseconds(timeout_ms + 2000)).get(), r, &frame);
}

cv::Mat frame_image(const v1::Frame& f) {
  const int type = f.channels() == 1 ? CV_8UC1 : CV_8UC3;
  cv::Mat m(f.height(), f.width(), type, const_cast<char*>(f.data().data()));
  cv::Mat grey;
  if (f.channels() == 1) grey = m.clone();
  else cv::cvtColor(m, grey, cv::COLOR_RGB2GRAY);
  return grey;
}

// PSNR of `image` against the test scene's texture at the view's surface points, over the
// pixels some camera covers (non-black) where `usable(surface point in vision)` holds.
template <typename Usable>
double psnr_against_scene(const cv::Mat& image, const std::string& view_yaml, const Pose& T_vision_frame,
                          Usable&& usable, size_t* compared = nullptr) {
  const auto reader = YamlReader::from_string(view_yaml, "view");
  const ViewSpec spec = parse_view(reader, reader.root(), "view");
  const auto view = View::create(spec);
  const Pose T_vision_view = T_vision_frame * spec.T_frame_view();
  cv::Mat on_surface;
  cv::Mat expected = synthetic::texture_at_view(*view, T_vision_view, &on_surface);
  cv::Mat expected_grey;
  cv::cvtColor(expected, expected_grey, cv::COLOR_BGR2GRAY);
  double error = 0;
  size_t n = 0;
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      if (!on_surface.at<uint8_t>(v, u) || image.at<uint8_t>(v, u) == 0) continue;
      Vec3 p;
      if (!view->pixel_to_point(u, v, p) || !usable(T_vision_view * p)) continue;
      const double d = double(image.at<uint8_t>(v, u)) - expected_grey.at<uint8_t>(v, u);
      error += d * d;
      ++n;
    }
  }
  if (compared) *compared = n;
  return n == 0 ? 0 : 10 * std::log10(255.0 * 255.0 / (error / n));
}


// Reads a view's frames on its own thread, noting when each arrived.
class FrameReader {
 public:
  FrameReader(v1::Omniview::Stub& stub, const std::string& view) {
    context_ = make_context("", 60s);
    v1::StreamFramesRequest r;
    r.set_view(view);
    r.set_encoding(v1::JPEG);
    r.set_stale_frames(true);
    reader_ = stub.StreamFrames(context_.get(), r);
    thread_ = std::thread([this] {
      v1::Frame f;
      while (reader_->Read(&f)) {
        std::lock_guard lock(mutex_);
        if (f.stale()) {
          stale_.push_back({Clock::now(), f.stale_reason()});
        } else {
          arrivals_.push_back(Clock::now());
          captures_.push_back(std::chrono::system_clock::time_point(
              std::chrono::seconds(f.capture_time().seconds()) +
              std::chrono::duration_cast<std::chrono::system_clock::duration>(
                  std::chrono::nanoseconds(f.capture_time().nanos()))));
        }
      }
    });
  }
  ~FrameReader() {
    context_->TryCancel();
    thread_.join();
  }
  // Live frames (stale ones, the last picture sent again while the robot is silent, apart).
  size_t frames() const {
    std::lock_guard lock(mutex_);
    return arrivals_.size();
  }
  struct Stale {
    Clock::time_point arrival;
    std::string reason;
  };
  std::vector<Stale> stale_frames() const {
    std::lock_guard lock(mutex_);
    return stale_;
  }
  // Live frames of images captured after `t` (the frames' capture_time, on the wall clock).
  size_t captured_after(std::chrono::system_clock::time_point t) const {
    std::lock_guard lock(mutex_);
    return std::count_if(captures_.begin(), captures_.end(), [&](auto c) { return c > t; });
  }
  // The first frame that arrived after `t`, if any.
  std::optional<Clock::time_point> first_after(Clock::time_point t) const {
    std::lock_guard lock(mutex_);
    for (const auto& a : arrivals_) {
      if (a > t) return a;
    }
    return std::nullopt;
  }

 private:
  std::unique_ptr<grpc::ClientContext> context_;
  std::unique_ptr<grpc::ClientReader<v1::Frame>> reader_;
  mutable std::mutex mutex_;
  std::vector<Clock::time_point> arrivals_;
  std::vector<std::chrono::system_clock::time_point> captures_;
  std::vector<Stale> stale_;
  std::thread thread_;
};


// Neither log may hold the robot's password or anything token-like.
void expect_no_secrets(const std::string& log, const std::string& password) {
  EXPECT_EQ(log.find(password), std::string::npos) << "the password is in a log:\n" << log;
  EXPECT_EQ(log.find("Bearer"), std::string::npos) << log;
  EXPECT_EQ(log.find("eyJ"), std::string::npos) << "a JWT is in a log:\n" << log;  // base64 of '{"'
}

std::string mock_password(const TempDir& dir) {
  return YAML::LoadFile(SpotMock::credentials(dir))["password"].as<std::string>();
}

TEST(SpotSource, DefaultViewsStreamAndMatchTheMocksScene) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port, "test", {"--supersample", "2"});
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir)));
  auto stub = make_stub(daemon.address());

  // Nobody watches yet: the source logs in and reads the cameras, but pulls no image.
  ASSERT_TRUE(eventually([&] { return source_status(*stub).connected(); }, 10s)) << daemon.log();
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(mock_control(mock, "--counters").at("get_image_calls"), 0) << "images pulled with nobody watching";

  v1::ListCamerasResponse cams;
  ASSERT_TRUE(stub->ListCameras(make_context().get(), v1::ListCamerasRequest(), &cams).ok());
  EXPECT_EQ(cams.cameras_size(), 5);

  for (const char* name : {"front", "birdseye"}) {
    v1::Frame f;
    ASSERT_TRUE(snapshot(*stub, name, f).ok()) << name << "\n" << daemon.log();
    EXPECT_EQ(f.width(), std::string(name) == "front" ? 1024 : 800);
    EXPECT_GT(f.coverage(), std::string(name) == "front" ? 0.6 : 0.85) << name;
  }

  // The shipped bird's-eye view stands on footprint, the ground below the body: in the
  // mock's world that is the floor z = 0 the test scene textures, up to its wall at x = 3.
  // (Without the robot drawn in: this compares the cameras' geometry.)
  v1::UpdateViewRequest no_robot;
  no_robot.set_name("birdseye");
  no_robot.mutable_set()->set_overlay(false);
  v1::View updated;
  ASSERT_TRUE(stub->UpdateView(make_context().get(), no_robot, &updated).ok());
  v1::Frame bird;
  ASSERT_TRUE(snapshot(*stub, "birdseye", bird).ok());
  size_t n = 0;
  const double bird_db = psnr_against_scene(
      frame_image(bird), bird.camera().yaml(), Pose::Identity(),
      [](const Vec3& p) { return p.x() < spot_mock::kTestWallX - 0.1; }, &n);
  std::cout << "birdseye vs the scene: " << bird_db << " dB over " << n << " pixels\n";
  EXPECT_GT(n, 200000u);
  EXPECT_GT(bird_db, 35);  // measured 39.4 (the mock's JPEG and grazing floor views)

  // A front view whose plane is the scene's wall (3 m ahead of the body) checks the front
  // cameras' geometry: their crossing, roll and pitch.
  v1::CreateViewRequest create;
  auto* spec = create.mutable_spec();
  spec->set_name("wall");
  spec->set_type(v1::PERSPECTIVE);
  spec->set_width(640);
  spec->set_height(320);
  spec->set_frame("body");
  spec->set_hfov_deg(110);
  spec->set_distance(spot_mock::kTestWallX);
  // Absolute intensities against the scene: no gains. The view's plane cuts the floor below
  // the wall, where the two front cameras see different patches, and the gains measured
  // there come out 1-2 % off 1 (42.6 dB instead of 48.6): brightness, not the geometry
  // this checks.
  spec->set_gain_compensation(false);
  v1::View created;
  ASSERT_TRUE(stub->CreateView(make_context().get(), create, &created).ok());
  v1::Frame wall;
  ASSERT_TRUE(snapshot(*stub, "wall", wall).ok());
  Pose T_vision_body = Pose::Identity();
  T_vision_body.translation().z() = spot_mock::kBodyHeightM;
  const double wall_db = psnr_against_scene(
      frame_image(wall), wall.camera().yaml(), T_vision_body, [](const Vec3& p) { return p.z() > 0.1; }, &n);
  std::cout << "front wall vs the scene: " << wall_db << " dB over " << n << " pixels\n";
  EXPECT_GT(n, 60000u);
  EXPECT_GT(wall_db, 44);  // measured 48.6
}


TEST(SpotSource, PullsOnlyTheCamerasWatchedViewsNeed) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port);
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir)));
  auto stub = make_stub(daemon.address());
  // A narrow view looking back and down: the back camera alone sees it.
  v1::CreateViewRequest create;
  auto* spec = create.mutable_spec();
  spec->set_name("behind");
  spec->set_type(v1::PERSPECTIVE);
  spec->set_width(320);
  spec->set_height(240);
  spec->set_frame("body");
  spec->set_yaw_deg(180);
  spec->set_pitch_deg(35);
  spec->set_hfov_deg(40);
  v1::View created;
  const grpc::Status made = stub->CreateView(make_context().get(), create, &created);
  ASSERT_TRUE(made.ok()) << made.error_message() << " daemon alive: " << (::kill(daemon.pid(), 0) == 0) << " rss " << daemon.rss_kb() << "\n" << daemon.log();
  {
    FrameReader reader(*stub, "behind");
    ASSERT_TRUE(eventually([&] { return reader.frames() >= 10; }, 15s)) << daemon.log();
  }
  const auto counters = mock_control(mock, "--counters");
  EXPECT_GE(counters.at("image_requests.back_fisheye_image"), 10);
  for (const char* unwatched : {"frontleft_fisheye_image", "frontright_fisheye_image", "left_fisheye_image",
                                "right_fisheye_image"}) {
    const auto it = counters.find(std::string("image_requests.") + unwatched);
    EXPECT_TRUE(it == counters.end() || it->second == 0) << unwatched << " was pulled";
  }
  // A view of the sky, which no camera sees, still gets its black frames saying coverage 0
  // (one camera is pulled so that image sets keep coming), not "not delivering images".
  spec->set_name("sky");
  spec->set_yaw_deg(0);
  spec->set_pitch_deg(-60);
  ASSERT_TRUE(stub->CreateView(make_context().get(), create, &created).ok());
  v1::Frame sky;
  const grpc::Status shot = snapshot(*stub, "sky", sky);
  ASSERT_TRUE(shot.ok()) << shot.error_message();
  EXPECT_EQ(sky.coverage(), 0);
  // Nobody watches any more: the pulling stops (calls in flight and a loaded machine may
  // take a moment), and stays stopped.
  double calls = -1;
  ASSERT_TRUE(eventually(
      [&] {
        const double before = mock_control(mock, "--counters").at("get_image_calls");
        std::this_thread::sleep_for(400ms);
        calls = mock_control(mock, "--counters").at("get_image_calls");
        return calls == before;
      },
      10s))
      << "images still pulled with nobody watching; the daemon's status (who still watches):\n"
      << [&] {
           v1::Status st;
           stub->GetStatus(make_context().get(), v1::GetStatusRequest(), &st);
           return st.DebugString();
         }()
      << daemon.log();
  std::this_thread::sleep_for(1s);
  EXPECT_EQ(mock_control(mock, "--counters").at("get_image_calls"), calls);
}

// A small view of the back camera alone: cheap to render, one camera to pull.
std::string small_back_view() {
  return "views:\n  - {name: behind, type: perspective, source: spot, width: 160, height: 120,"
         " frame: body, pose: {ypr_deg: [180, 35, 0]}, hfov_deg: 40}\n";
}

// Over Wi-Fi a round trip takes longer than a 15 Hz cycle: GetImage calls overlap
// (requests_in_flight, 2 by default), so the rate is not one image set per round trip, and
// the joint angles, read beside them, never hold the images up.
TEST(SpotSource, OverlappingCallsBeatTheRoundTripOnASlowLink) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port, "test", {"--latency-ms", "250"});
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir), small_back_view()));
  auto stub = make_stub(daemon.address());
  FrameReader reader(*stub, "behind");
  ASSERT_TRUE(eventually([&] { return reader.frames() >= 3; }, 20s)) << daemon.log();
  const size_t before = reader.frames();
  std::this_thread::sleep_for(3s);
  const double rate = static_cast<double>(reader.frames() - before) / 3.0;
  std::cout << "image sets per second at a 250 ms round trip: " << rate << "\n";
  // One call at a time: at most 4 per second; two overlapping: up to 8.
  EXPECT_GT(rate, 5.5 / test_time_scale()) << daemon.log();
  EXPECT_EQ(source_status(*stub).errors(), 0u) << source_status(*stub).DebugString();
}

// A robot's clock is not ours: images carry its acquisition time, and the source turns it
// into ours with the robot's time-sync service, so a frame's capture time and age are true
// (over a 200 ms link: the estimate takes the round trip out).
TEST(SpotSource, CaptureTimesAreOnOurClockHoweverTheRobotsIsSet) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port, "test", {"--clock-offset-ms", "-7000", "--latency-ms", "200"});
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir), small_back_view()));
  auto stub = make_stub(daemon.address());
  v1::Frame f;
  ASSERT_TRUE(snapshot(*stub, "behind", f).ok()) << daemon.log();
  const double age_s = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count() -
                       (static_cast<double>(f.capture_time().seconds()) + f.capture_time().nanos() * 1e-9);
  // Over a 200 ms round trip an image is at least the way back (100 ms) old when it arrives.
  EXPECT_GE(age_s, 0.09) << "captured before it arrived";
  EXPECT_LT(age_s, 1.0 * test_time_scale()) << "the robot's clock is 7 s behind; uncorrected the age would be 7 s";
  // The estimate is as good as the link is symmetric (a few ms off under load), so the
  // figure is compared as a number, not as the digits "7.0".
  const std::string log = daemon.log();
  const size_t said = log.find("robot clock ");
  ASSERT_NE(said, std::string::npos) << log;
  EXPECT_NEAR(std::strtod(log.c_str() + said + std::strlen("robot clock "), nullptr), 7.0, 0.05 * test_time_scale())
      << log;
  EXPECT_NE(log.find("behind ours"), std::string::npos) << log;
}

TEST(SpotSource, ColourAndGreyRobotsRawAndJpegThroughTheFallbackFormats) {
  const std::string rgb_raw = "    image_format: raw\n    pixel_format: rgb\n";
  {
    // Asking a greyscale robot for colour: the fallback list lets it answer in grey.
    TempDir dir;
    const int port = free_port();
    SpotMock mock(dir, port, "room");
    DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir), shipped_views(), rgb_raw));
    auto stub = make_stub(daemon.address());
    v1::Frame f;
    ASSERT_TRUE(snapshot(*stub, "front", f).ok()) << daemon.log();
    EXPECT_EQ(f.channels(), 1);
    EXPECT_EQ(source_status(*stub).errors(), 0u) << source_status(*stub).DebugString();
  }
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port, "room", {"--rgb"});
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir), shipped_views(), rgb_raw));
  auto stub = make_stub(daemon.address());
  v1::Frame f;
  ASSERT_TRUE(snapshot(*stub, "front", f).ok()) << daemon.log();
  ASSERT_EQ(f.channels(), 3) << "colour cameras give a colour view";
  const cv::Mat rgb(f.height(), f.width(), CV_8UC3, const_cast<char*>(f.data().data()));
  std::vector<cv::Mat> planes;
  cv::split(rgb, planes);
  EXPECT_GT(cv::norm(planes[0], planes[2], cv::NORM_L1) / planes[0].total(), 1.0) << "not grey";
  EXPECT_EQ(source_status(*stub).errors(), 0u) << source_status(*stub).DebugString();
}

// The shipped bird's-eye view draws the robot (config/spot.yaml's robot_models) where it
// stands, with the leg angles the robot reports; turning the overlay off shows the blind
// spot under the body again.
TEST(SpotSource, BirdseyeShowsTheRobotWithItsReportedLegs) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port);
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir)));
  auto stub = make_stub(daemon.address());
  v1::Frame with;
  ASSERT_TRUE(snapshot(*stub, "birdseye", with).ok()) << daemon.log();
  ASSERT_EQ(with.channels(), 3) << "the robot is drawn in colour over the grey cameras";
  const cv::Mat image(with.height(), with.width(), CV_8UC3, const_cast<char*>(with.data().data()));
  const cv::Vec3b centre = image.at<cv::Vec3b>(with.height() / 2, with.width() / 2);  // RGB: body below
  EXPECT_GT(centre[0], 150) << "yellow body at the footprint";
  EXPECT_GT(centre[1], 120);
  EXPECT_LT(centre[2], 90);

  // A leg moves on the robot while nobody watches: the next snapshot shows it (the source
  // reads the pose again after a pause), and nothing else changes.
  mock_control(mock, "--joint fl.hy=0 --joint fl.kn=0");
  std::this_thread::sleep_for(1500ms);
  v1::Frame moved;
  ASSERT_TRUE(snapshot(*stub, "birdseye", moved).ok());
  ASSERT_NE(moved.data(), with.data()) << "the leg moved";
  const cv::Mat after(moved.height(), moved.width(), CV_8UC3, const_cast<char*>(moved.data().data()));
  cv::Mat diff;
  cv::absdiff(image, after, diff);
  cv::Mat changed;
  cv::cvtColor(diff, changed, cv::COLOR_RGB2GRAY);
  changed = changed > 30;
  EXPECT_GT(cv::countNonZero(changed), 50);
  const cv::Rect where = cv::boundingRect(changed);
  const cv::Rect robot_area(with.width() / 2 - 100, with.height() / 2 - 100, 200, 200);
  EXPECT_EQ(where & robot_area, where) << "changes outside the robot: " << where;

  // The robot's report wins over positions set through the API, and says so.
  v1::SetJointPositionsRequest set;
  (*set.mutable_positions())["fl.kn"] = -2.0;
  v1::JointPositions joints;
  ASSERT_TRUE(stub->SetJointPositions(make_context().get(), set, &joints).ok());
  for (const auto& j : joints.joints()) {
    EXPECT_EQ(j.origin(), v1::Joint::SOURCE) << j.name() << " is reported by the robot";
    if (j.name() == "fl.kn") {
      EXPECT_NEAR(j.position(), 0.0, 1e-6) << "as the robot reports it";
    }
  }

  v1::UpdateViewRequest off;
  off.set_name("birdseye");
  off.mutable_set()->set_overlay(false);
  v1::View updated;
  ASSERT_TRUE(stub->UpdateView(make_context().get(), off, &updated).ok());
  v1::Frame without;
  ASSERT_TRUE(snapshot(*stub, "birdseye", without).ok());
  EXPECT_EQ(without.channels(), 1);
  EXPECT_EQ(static_cast<uint8_t>(without.data()[(without.height() / 2) * without.width() + without.width() / 2]), 0)
      << "the cameras cannot see under the body";
}

TEST(SpotSource, WrongPasswordIsClearAndNeverTripsTheLockout) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port);
  const std::string wrong = dir.write("wrong.yaml", "username: user\npassword: not-the-password-42\n");
  DaemonProcess daemon(dir, daemon_config(dir, port, wrong));
  auto stub = make_stub(daemon.address());
  ASSERT_TRUE(eventually([&] { return source_status(*stub).message().find("login refused") != std::string::npos; }, 10s))
      << source_status(*stub).DebugString() << daemon.log();
  const v1::SourceStatus st = source_status(*stub);
  EXPECT_FALSE(st.connected());
  EXPECT_NE(st.message().find("user 'user'"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("credentials"), std::string::npos) << "says what to check: " << st.message();
  // Views answer with the source's state instead of hanging.
  v1::Frame f;
  EXPECT_FALSE(snapshot(*stub, "front", f, 1000).ok());
  std::this_thread::sleep_for(2s);
  EXPECT_LE(mock_control(mock, "--counters").at("logins_failed"), 2) << "retrying too often: the robot locks after 6";
  expect_no_secrets(daemon.log(), "not-the-password-42");
  expect_no_secrets(daemon.log(), mock_password(dir));
}

TEST(SpotSource, ViewsResumeWithinTwoSecondsOfTheRobotsReturn) {
  TempDir dir;
  const int port = free_port();
  auto mock = std::make_unique<SpotMock>(dir, port);
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir)));
  auto stub = make_stub(daemon.address());
  FrameReader reader(*stub, "birdseye");
  ASSERT_TRUE(eventually([&] { return reader.frames() >= 5; }, 15s)) << daemon.log();

  const auto gone = Clock::now();
  mock->stop(SIGKILL);  // the robot walks out of Wi-Fi range, or reboots
  mock.reset();
  ASSERT_TRUE(eventually([&] { return !source_status(*stub).connected(); }, 10s)) << daemon.log();
  EXPECT_NE(source_status(*stub).message().find("retrying"), std::string::npos) << source_status(*stub).message();
  std::this_thread::sleep_for(3s);  // long enough for any backoff to have grown

  // Meanwhile the client got the last picture again, about once a second, marked stale
  // with the reason, and no live frame (a second one may take longer under a sanitizer).
  const auto scaled = std::chrono::milliseconds(static_cast<int64_t>(3000 * test_time_scale()));
  ASSERT_TRUE(eventually([&] { return reader.stale_frames().size() >= 2; }, scaled)) << daemon.log();
  const auto stale = reader.stale_frames();
  EXPECT_LT(std::chrono::duration<double>(stale.front().arrival - gone).count(), 3.0 * test_time_scale());
  EXPECT_NE(stale.back().reason.find("no new images from source 'spot'"), std::string::npos) << stale.back().reason;
  EXPECT_NE(stale.back().reason.find("not connected"), std::string::npos) << stale.back().reason;
  EXPECT_LE(stale.size(), 1 + std::chrono::duration<double>(Clock::now() - gone).count() / 0.9) << "about 1 Hz";
  const size_t live_before = reader.frames();

  mock = std::make_unique<SpotMock>(dir, port);
  const auto back = Clock::now();
  ASSERT_TRUE(eventually([&] { return reader.first_after(back).has_value(); }, 10s)) << daemon.log();
  const double resumed_s = std::chrono::duration<double>(*reader.first_after(back) - back).count();
  std::cout << "frames resumed " << resumed_s << " s after the robot was back\n";
  EXPECT_LT(resumed_s, 2.0 * test_time_scale());
  EXPECT_GT(reader.frames(), live_before);
  EXPECT_TRUE(source_status(*stub).connected());
  expect_no_secrets(daemon.log(), mock_password(dir));
  expect_no_secrets(mock->log(), mock_password(dir));
}

TEST(SpotSource, BadImagesFailedCallsAndExpiredTokensAreSkippedAndCounted) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port, "test",
                {"--corrupt-probability", "0.2", "--image-error-probability", "0.1", "--wrong-size-probability", "0.1",
                 "--fail-probability", "0.1"});
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir)));
  auto stub = make_stub(daemon.address());
  FrameReader reader(*stub, "birdseye");
  ASSERT_TRUE(eventually([&] { return reader.frames() >= 10; }, 20s)) << daemon.log();
  const double logins = mock_control(mock, "--counters").at("logins_ok");
  mock_control(mock, "--expire-tokens");
  const size_t before = reader.frames();
  ASSERT_TRUE(eventually([&] { return reader.frames() >= before + 10; }, 20s)) << daemon.log();
  EXPECT_GT(mock_control(mock, "--counters").at("logins_ok"), logins) << "logged in again";
  const v1::SourceStatus st = source_status(*stub);
  EXPECT_GT(st.errors(), 0u) << st.DebugString();
  EXPECT_EQ(daemon.stop(SIGTERM), 0) << daemon.log();
  expect_no_secrets(daemon.log(), mock_password(dir));
}

// A camera image cut short decodes in part (libjpeg fills the rest grey, with a warning):
// an error for that camera like one that does not decode at all, never a live frame with
// a flat grey patch (issue 33). With every image damaged no live frame comes at all; the
// client gets the last good picture again, marked stale.
TEST(SpotSource, DamagedImagesNeverReachAViewAsLivePicture) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port);
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir)));
  auto stub = make_stub(daemon.address());
  FrameReader reader(*stub, "front");
  ASSERT_TRUE(eventually([&] { return reader.frames() >= 5; }, 15s)) << daemon.log();
  mock_control(mock, "--set corrupt_probability=1");  // half cut to a third, half garbled
  // Every image captured from now on is damaged. Frames of images captured before may still
  // be on their way (calls in flight, a view rendering): they are told apart by capture time,
  // with a margin for the robot clock's offset (known to within half a round trip).
  const auto damaged_from = std::chrono::system_clock::now() + 100ms;
  const uint64_t errors = source_status(*stub).errors();
  ASSERT_TRUE(eventually([&] { return source_status(*stub).errors() >= errors + 36; }, 30s)) << daemon.log();
  EXPECT_EQ(reader.captured_after(damaged_from), 0u) << "live frames rendered from damaged images";
  ASSERT_TRUE(eventually([&] { return !reader.stale_frames().empty(); }, 10s)) << daemon.log();
  EXPECT_NE(source_status(*stub).message().find("JPEG"), std::string::npos) << source_status(*stub).message();
}

// Half the robot's calls fail, yet frames keep coming: the source is connected but
// degraded, with its failure rate, rather than "not connected" (issue 33).
TEST(SpotSource, StatusSaysDegradedWithTheFailureRateWhileFramesStillCome) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port);
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir)));
  auto stub = make_stub(daemon.address());
  FrameReader reader(*stub, "birdseye");
  ASSERT_TRUE(eventually([&] { return reader.frames() >= 5; }, 15s)) << daemon.log();
  v1::SourceStatus healthy = source_status(*stub);
  EXPECT_TRUE(healthy.connected());
  EXPECT_FALSE(healthy.degraded());
  EXPECT_LT(healthy.failure_rate(), 0.1);

  mock_control(mock, "--set fail_probability=0.5");
  ASSERT_TRUE(eventually([&] { return source_status(*stub).degraded(); }, 20s)) << source_status(*stub).DebugString();
  const size_t before = reader.frames();
  // The rate averages ~20 calls, which come slower now (each failure backs off): it climbs
  // towards one half while frames keep coming and the source stays connected.
  int samples = 0, connected = 0;
  ASSERT_TRUE(eventually(
      [&] {
        const v1::SourceStatus st = source_status(*stub);
        ++samples;
        connected += st.connected();
        return st.failure_rate() >= 0.3 && reader.frames() >= before + 5;
      },
      30s))
      << source_status(*stub).DebugString();
  EXPECT_LT(source_status(*stub).failure_rate(), 0.85);
  EXPECT_GE(connected, samples * 8 / 10) << "said not connected while frames were coming";

  mock_control(mock, "--set fail_probability=0");
  ASSERT_TRUE(eventually([&] { return !source_status(*stub).degraded(); }, 20s)) << source_status(*stub).DebugString();
}

// The robot moves while nobody watches: the joints the API reports follow it (a
// robot-state read a second, no images), so `omniview joints` is never stale.
TEST(SpotSource, JointsAreCurrentWithNobodyWatching) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port);
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir)));
  auto stub = make_stub(daemon.address());
  ASSERT_TRUE(eventually([&] { return source_status(*stub).connected(); }, 10s)) << daemon.log();
  mock_control(mock, "--joint fl.kn=-0.7");
  const auto knee = [&] {
    v1::JointPositions joints;
    EXPECT_TRUE(stub->GetJointPositions(make_context().get(), v1::GetJointPositionsRequest(), &joints).ok());
    for (const auto& j : joints.joints()) {
      if (j.name() == "fl.kn" && j.origin() == v1::Joint::SOURCE) return j.position();
    }
    return 0.0;
  };
  const auto scale = std::chrono::milliseconds(static_cast<int64_t>(4000 * test_time_scale()));
  EXPECT_TRUE(eventually([&] { return std::abs(knee() + 0.7) < 1e-6; }, scale)) << "fl.kn " << knee();
  EXPECT_EQ(mock_control(mock, "--counters").at("get_image_calls"), 0) << "images pulled with nobody watching";
}

// The README's `views create` example for the demo's Spot shows what the left camera sees,
// not a mostly black picture (the old example was 58 % black); the shipped views of
// config/spot.yaml are covered too (the front view without its black notch at the top).
TEST(SpotSource, TheReadmesCreatedViewIsCovered) {
  TempDir dir;
  const int port = free_port();
  SpotMock mock(dir, port, "room");
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir)));
  auto stub = make_stub(daemon.address());
  ASSERT_TRUE(eventually([&] { return source_status(*stub).connected(); }, 10s)) << daemon.log();
  const auto r = run_process(std::string(OMNIVIEW_CLI) + " views create --file " + OMNIVIEW_SOURCE_DIR +
                             "/config/examples/views/front_perspective.yaml --set name=left --set frame=body"
                             " --set xyz=0,0,0 --set yaw_deg=90 --set pitch_deg=35 --set hfov_deg=80"
                             " --set distance=1.5 --server " + daemon.address());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  // Views nobody watches get their maps (and so their coverage) once the source has
  // announced its rig, on the render thread: wait until every view has one.
  v1::Status st;
  const auto all_mapped = [&] {
    if (!stub->GetStatus(make_context().get(), v1::GetStatusRequest(), &st).ok()) return false;
    for (const auto& v : st.views()) {
      if (v.coverage() <= 0) return false;
    }
    return st.views_size() == 4;
  };
  EXPECT_TRUE(eventually(all_mapped, std::chrono::milliseconds(static_cast<int64_t>(5000 * test_time_scale()))));
  for (const auto& v : st.views()) {
    std::cout << "view " << v.name() << ": coverage " << v.coverage() << "\n";
    const std::map<std::string, double> least = {{"left", 0.97}, {"front", 0.9999}, {"panorama", 0.95}, {"birdseye", 0.85}};
    if (least.count(v.name())) {
      EXPECT_GT(v.coverage(), least.at(v.name())) << v.name();  // front: no notch at the top
    }
  }
}

// The robot connects after the daemon started (no cameras known until then): while a
// watched view's map is rebuilt for the cameras the robot announced, GetStatus says
// `map_pending` instead of reporting the old map's 0 % coverage, which `omniview status`
// would otherwise show and warn about.
TEST(SpotSource, StatusSaysAMapIsPendingRatherThanUncoveredWhenTheRobotConnects) {
  TempDir dir;
  const int port = free_port();
  { SpotMock first(dir, port); }  // leaves its CA and credentials, which the daemon's config names
  DaemonProcess daemon(dir, daemon_config(dir, port, SpotMock::credentials(dir)));
  auto stub = make_stub(daemon.address());
  FrameReader reader(*stub, "front");
  SpotMock mock(dir, port);
  int pending_seen = 0, polls = 0;
  const auto covered = [&] {
    v1::Status st;
    if (!stub->GetStatus(make_context().get(), v1::GetStatusRequest(), &st).ok()) return false;
    ++polls;
    bool delivering = false;
    for (const auto& s : st.sources()) delivering |= s.name() == "spot" && s.connected() && s.frames() > 0;
    for (const auto& v : st.views()) {
      if (v.name() != "front") continue;
      if (v.map_pending()) ++pending_seen;
      if (delivering && !v.map_pending()) {
        EXPECT_GT(v.coverage(), 0.9) << "poll " << polls;
      }
      return delivering && !v.map_pending() && reader.frames() > 0;
    }
    ADD_FAILURE() << "no view 'front' in status";
    return true;
  };
  ASSERT_TRUE(eventually(covered, std::chrono::milliseconds(static_cast<int64_t>(15000 * test_time_scale()))))
      << daemon.log();
  std::cout << polls << " polls, map pending in " << pending_seen << "\n";
}

}  // namespace
}  // namespace omniview::testing
