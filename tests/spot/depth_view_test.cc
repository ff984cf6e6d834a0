// Depth-aware views served by the daemon (issue 32): spot-mock's lidar and cameras in its
// test scene (the floor z = 0 and a wall at x = 3 m), the real omniviewd, real gRPC
// clients. The same view with `depth: fixed` (a plane 8 m ahead) and `depth: measured`
// is compared with what a camera at the view's pose sees of the mock's own scene
// (ray-cast), and its clicks (PixelToRay) with where its rays meet that scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <sstream>
#include <thread>

#include <opencv2/core.hpp>

#include "core/io/image_codec.h"
#include "core/io/yaml_reader.h"
#include "core/synthetic/scene.h"
#include "core/view/view.h"
#include "core/view/view_yaml.h"
#include "server/convert/convert.h"
#include "spot_adapter/mock/world/mock_scene.h"
#include "tests/server/daemon_process.h"
#include "tests/spot_mock/spot_mock_process.h"

namespace omniview::testing {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// A view looking ahead and down from the body: the floor from 1 m and the wall at 3 m,
// seen by both front cameras (their seam runs down the middle). As a user would set it up:
// the surface ends at the floor (`ground`), so what neither surface nor lidar covers (the
// floor the lidar's rings do not reach near the robot) is seen right either way; the plane
// 8 m ahead stands for any guess that is not the wall.
v1::ViewSpec front_view(const std::string& name, v1::Depth depth) {
  v1::ViewSpec s;
  s.set_name(name);
  s.set_type(v1::PERSPECTIVE);
  s.set_source("spot");
  s.set_frame("body");
  s.set_width(320);
  s.set_height(240);
  s.set_hfov_deg(80);
  s.set_pitch_deg(10);
  s.set_distance(8);
  s.set_ground(true);
  s.set_ground_z(-spot_mock::kBodyHeightM);
  s.set_depth(depth);
  return s;
}

// Reads a view's RAW frames on its own thread and keeps the newest.
class LatestFrame {
 public:
  LatestFrame(v1::Omniview::Stub& stub, const std::string& view) {
    context_ = make_context("", 300s);
    v1::StreamFramesRequest r;
    r.set_view(view);
    r.set_encoding(v1::RAW);
    reader_ = stub.StreamFrames(context_.get(), r);
    thread_ = std::thread([this] {
      v1::Frame f;
      while (reader_->Read(&f)) {
        std::lock_guard lock(mutex_);
        latest_ = f;
        ++count_;
      }
    });
  }
  ~LatestFrame() {
    context_->TryCancel();
    thread_.join();
  }
  v1::Frame get() const {
    std::lock_guard lock(mutex_);
    return latest_;
  }
  size_t count() const {
    std::lock_guard lock(mutex_);
    return count_;
  }

 private:
  std::unique_ptr<grpc::ClientContext> context_;
  std::unique_ptr<grpc::ClientReader<v1::Frame>> reader_;
  std::thread thread_;
  mutable std::mutex mutex_;
  v1::Frame latest_;
  size_t count_ = 0;
};

// What a camera at the view's pose sees of the mock's scene (grey, one ray per pixel
// centre; 0 where the ray hits nothing), and each pixel's hit in the body frame.
struct Truth {
  cv::Mat grey;
  std::vector<Vec3> hit_body;  // NaN: none
};

Truth ray_cast(const v1::View& described) {
  const auto reader = YamlReader::from_string(described.yaml(), "view");
  const ViewSpec spec = parse_view(reader, reader.root(), "view");
  const auto view = View::create(spec);
  const Rig rig = spot_mock::mock_rig();
  const Pose T_vision_body = rig.frames().lookup(spot_mock::kWorldFrame, spot_mock::kBodyFrame);
  const Pose T_body_view = from_proto(described.pose());  // the view in the robot frame "body"
  const Pose T_vision_view = T_vision_body * T_body_view;
  const synthetic::Scene scene = spot_mock::make_scene(spot_mock::SceneKind::kTest);
  Truth t;
  t.grey = cv::Mat(spec.height, spec.width, CV_8UC1, cv::Scalar(0));
  t.hit_body.assign(size_t(spec.width) * spec.height, Vec3::Constant(std::nan("")));
  for (int v = 0; v < spec.height; ++v) {
    for (int u = 0; u < spec.width; ++u) {
      Vec3 dir;
      if (!view->pixel_to_direction(u, v, dir)) continue;
      const auto hit = scene.intersect(T_vision_view.translation(), T_vision_view.linear() * dir);
      if (!hit) continue;
      const Vec3 bgr = scene.colour(*hit);
      t.grey.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(0.114 * bgr[0] + 0.587 * bgr[1] + 0.299 * bgr[2]);
      t.hit_body[size_t(v) * spec.width + u] = T_vision_body.inverse() * hit->point;
    }
  }
  return t;
}

// On the wall, below where the lidar's top ring meets it (+15 deg from 0.2 m above the
// body's origin: 1.0 m at the wall); above that the view falls back to its plane.
bool on_wall(const Vec3& hit_body) {
  return std::abs(hit_body.x() - spot_mock::kTestWallX) < 0.01 && hit_body.z() < 0.9;
}

// PSNR of a RAW grey frame against the truth, over the pixels both show (and, with
// `wall_only`, whose truth is on the wall).
double psnr(const v1::Frame& f, const Truth& truth, size_t* compared = nullptr, bool wall_only = false) {
  EXPECT_EQ(f.channels(), 1);
  const cv::Mat image(f.height(), f.width(), CV_8UC1, const_cast<char*>(f.data().data()));
  double error = 0;
  size_t n = 0;
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      if (image.at<uint8_t>(v, u) == 0 || truth.grey.at<uint8_t>(v, u) == 0) continue;
      if (wall_only && !on_wall(truth.hit_body[size_t(v) * image.cols + u])) continue;
      const double d = double(image.at<uint8_t>(v, u)) - truth.grey.at<uint8_t>(v, u);
      error += d * d;
      ++n;
    }
  }
  if (compared) *compared = n;
  return n == 0 ? 0 : 10 * std::log10(255.0 * 255.0 / std::max(error / n, 1e-9));
}

class DepthViews : public ::testing::Test {
 protected:
  void SetUp() override {
    mock_ = std::make_unique<SpotMockProcess>(dir_.path(), std::vector<std::string>{"--scene", "test"});
    std::ostringstream config;
    config << "listen: 127.0.0.1:0\n"
           << "sources:\n"
           << "  - name: spot\n"
           << "    type: spot\n"
           << "    robot: 127.0.0.1:" << mock_->port() << "\n"
           << "    ca_file: " << mock_->certs_dir() << "/ca.pem\n"
           << "    credentials_file: " << mock_->credentials_file() << "\n"
           << "    rate_hz: 10\n"
           << source_config();
    daemon_ = std::make_unique<DaemonProcess>(dir_, config.str());
    stub_ = make_stub(daemon_->address());
    ASSERT_TRUE(eventually_within([&] { return status().sources_size() > 0 && status().sources(0).connected(); }, 20s))
        << daemon_->log();
    for (const auto depth : {v1::FIXED, v1::MEASURED}) {
      v1::CreateViewRequest r;
      *r.mutable_spec() = front_view(depth == v1::FIXED ? "fixed" : "measured", depth);
      v1::View created;
      const grpc::Status s = stub_->CreateView(make_context().get(), r, &created);
      ASSERT_TRUE(s.ok()) << s.error_message();
      EXPECT_EQ(created.spec().depth(), depth);
    }
  }

  // More keys of the spot source (YAML, indented as its keys).
  virtual std::string source_config() const { return ""; }

  v1::Status status() {
    v1::Status st;
    stub_->GetStatus(make_context().get(), v1::GetStatusRequest(), &st);
    return st;
  }
  v1::ViewStatus view_status(const std::string& name) {
    const v1::Status st = status();
    for (const auto& v : st.views()) {
      if (v.name() == name) return v;
    }
    ADD_FAILURE() << "no view " << name << " in the status";
    return {};
  }
  v1::PixelToRayResponse click(const std::string& view, double u, double v) {
    v1::PixelToRayRequest r;
    r.set_view(view);
    r.set_u(u);
    r.set_v(v);
    v1::PixelToRayResponse out;
    EXPECT_TRUE(stub_->PixelToRay(make_context().get(), r, &out).ok());
    return out;
  }

  TempDir dir_;
  std::unique_ptr<SpotMockProcess> mock_;
  std::unique_ptr<DaemonProcess> daemon_;
  std::unique_ptr<v1::Omniview::Stub> stub_;
};

TEST_F(DepthViews, AMeasuredViewStandsOnTheLidarsSceneWhereTheFixedOneGuesses) {
  // Only a fixed view watched: nobody needs the lidar.
  {
    LatestFrame fixed(*stub_, "fixed");
    ASSERT_TRUE(eventually_within([&] { return fixed.count() >= 3; }, 20s)) << daemon_->log();
    EXPECT_EQ(mock_->counter("get_point_cloud_calls"), 0) << "clouds pulled with no depth view watched";
    EXPECT_EQ(fixed.get().measured_depth(), 0);
  }
  const v1::ViewStatus unwatched = view_status("measured");
  EXPECT_EQ(unwatched.depth_geometry_age_s(), -1);
  EXPECT_NE(unwatched.depth_message().find("not watched"), std::string::npos) << unwatched.depth_message();

  LatestFrame fixed(*stub_, "fixed");
  LatestFrame measured(*stub_, "measured");
  ASSERT_TRUE(eventually_within([&] { return measured.get().measured_depth() > 0.2 && fixed.count() > 0; }, 30s))
      << "measured_depth " << measured.get().measured_depth() << "\n" << view_status("measured").DebugString()
      << daemon_->log();
  EXPECT_GT(mock_->counter("get_point_cloud_calls"), 0);

  // Read once the view stands on geometry: under a sanitizer the source can stall for
  // seconds (GetImage deadlines), and a depth view whose lidar is quiet for kFreshGeometry
  // goes back to its fixed surface until clouds come again (as it should on a robot).
  const auto on_geometry = [&](const v1::ViewStatus& s) {
    return s.depth_geometry_age_s() >= 0 && s.measured_depth() > 0.2 && s.depth_message().empty();
  };
  v1::ViewStatus st;
  EXPECT_TRUE(eventually_within([&] { return on_geometry(st = view_status("measured")); }, 30s)) << daemon_->log();
  std::cout << "depth view: " << st.DebugString();
  EXPECT_GE(st.depth_updates(), 1u);
  EXPECT_GE(st.depth_geometry_age_s(), 0);
  EXPECT_LT(st.depth_geometry_age_s(), 5 * test_time_scale());
  EXPECT_GT(st.depth_update_ms(), 0);
  EXPECT_GT(st.measured_depth(), 0.2);
  EXPECT_EQ(st.depth_message(), "");
  const v1::ViewStatus fixed_status = view_status("fixed");
  EXPECT_EQ(fixed_status.depth_updates(), 0u);
  EXPECT_EQ(fixed_status.measured_depth(), 0);

  // The pictures against what a camera at the view's pose sees of the scene: all of it,
  // and the wall the lidar reaches (where the two surfaces differ).
  // The picture compared is one that says it stood on measured depth: the newest frame may
  // be older than the status read above (a starved source delivers seconds apart under a
  // sanitizer), or made while the lidar was quiet, on the fixed surface (an ASan rehearsal
  // read 0.04 fps, and its newest frame was such a one).
  v1::Frame f_measured;
  ASSERT_TRUE(eventually_within([&] { return (f_measured = measured.get()).measured_depth() > 0.2; }, 30s))
      << "measured_depth of the newest frame " << f_measured.measured_depth() << "\n" << daemon_->log();
  const v1::Frame f_fixed = fixed.get();
  const Truth truth = ray_cast(f_measured.camera());
  if (const char* dir = std::getenv("OMNIVIEW_DEPTH_DUMP")) {  // the pictures, to look at
    const auto grey = [](const v1::Frame& f) { return cv::Mat(f.height(), f.width(), CV_8UC1, const_cast<char*>(f.data().data())); };
    std::vector<cv::Mat> rows = {grey(f_fixed), grey(f_measured), truth.grey};
    cv::Mat stack;
    cv::vconcat(rows, stack);
    write_image(std::string(dir) + "/depth_view_fixed_measured_truth.png", stack);
  }
  size_t n_fixed = 0, n_measured = 0, n_wall = 0;
  const double db_fixed = psnr(f_fixed, truth, &n_fixed), db_measured = psnr(f_measured, truth, &n_measured);
  const double wall_fixed = psnr(f_fixed, truth, nullptr, true), wall_measured = psnr(f_measured, truth, &n_wall, true);
  std::cout << "PSNR against the ray-cast scene: fixed " << db_fixed << " dB (" << n_fixed << " px), measured "
            << db_measured << " dB (" << n_measured << " px); on the wall (" << n_wall << " px): fixed " << wall_fixed
            << " dB, measured " << wall_measured << " dB\n";
  EXPECT_GT(n_measured, 0.5 * 320 * 240);
  ASSERT_GT(n_wall, 0.1 * 320 * 240);
  EXPECT_GT(wall_measured, wall_fixed + 6);
  EXPECT_GT(db_measured, db_fixed + 3);

  // A click on the wall (between the lidar's rings) lands where the pixel's ray meets it (body frame), not on the plane.
  int clicks = 0;
  for (const int u : {60, 160, 260}) {
    for (int v = 0; v < 240; v += 4) {
      const Vec3 expected = truth.hit_body[size_t(v) * 320 + u];
      if (!expected.allFinite() || !on_wall(expected) || expected.z() < 0.3 - spot_mock::kBodyHeightM ||
          expected.z() > 0.6) {
        continue;
      }
      // Clicked while the view stands on geometry (see above: it may drop it for a moment).
      Vec3 m = Vec3::Constant(NAN);
      const bool near = eventually_within(
          [&] {
            if (!on_geometry(view_status("measured"))) return false;
            const auto on_measured = click("measured", u, v);
            if (!on_measured.valid()) return false;
            m = from_proto(on_measured.surface_point());
            return (m - expected).norm() < 0.05 * expected.norm();
          },
          20s);
      EXPECT_TRUE(near) << "pixel " << u << "," << v << ": measured surface at " << m.transpose() << ", the wall at "
                        << expected.transpose();
      const Vec3 x = from_proto(click("fixed", u, v).surface_point());
      EXPECT_GT((x - expected).norm(), 1.0) << "the fixed plane lies on the wall here";
      ++clicks;
      break;
    }
  }
  EXPECT_EQ(clicks, 3) << "the view sees too little of the wall";
}

// The robot's depth cameras alone (no lidar: point_cloud_source none): the body cameras'
// `*_depth_in_visual_frame` images, asked for with the images while the view is watched.
class DepthImagesOnly : public DepthViews {
 protected:
  std::string source_config() const override { return "    point_cloud_source: none\n"; }
};

TEST_F(DepthImagesOnly, AMeasuredViewStandsOnTheDepthCamerasAlone) {
  LatestFrame fixed(*stub_, "fixed");
  LatestFrame measured(*stub_, "measured");
  ASSERT_TRUE(eventually_within([&] { return measured.get().measured_depth() > 0.5 && fixed.count() > 0; }, 30s))
      << "measured_depth " << measured.get().measured_depth() << "\n" << view_status("measured").DebugString()
      << daemon_->log();
  EXPECT_EQ(mock_->counter("get_point_cloud_calls"), 0) << "a lidar cloud was asked for with point_cloud_source: none";
  // Eventually, not at once: under a sanitizer the source can stall past kFreshGeometry
  // between the frame above and this read, and the view is then (rightly) between
  // geometries (an ASan rehearsal of stop 40 read the status in such a gap).
  std::string message;
  EXPECT_TRUE(eventually_within([&] { return (message = view_status("measured").depth_message()).empty(); }, 30s))
      << message;
  // The picture compared is one that says it stood on measured depth: the newest frame may
  // be older than the status read above (a starved source delivers seconds apart under a
  // sanitizer), or made while the lidar was quiet, on the fixed surface (an ASan rehearsal
  // read 0.04 fps, and its newest frame was such a one).
  v1::Frame f_measured;
  ASSERT_TRUE(eventually_within([&] { return (f_measured = measured.get()).measured_depth() > 0.2; }, 30s))
      << "measured_depth of the newest frame " << f_measured.measured_depth() << "\n" << daemon_->log();
  const v1::Frame f_fixed = fixed.get();
  const Truth truth = ray_cast(f_measured.camera());
  const double db_fixed = psnr(f_fixed, truth), db_measured = psnr(f_measured, truth);
  std::cout << "depth images only: PSNR fixed " << db_fixed << " dB, measured " << db_measured << " dB, "
            << 100 * f_measured.measured_depth() << " % on measured depth\n";
  EXPECT_GT(db_measured, db_fixed + 6);
}

// Watched again after a while, a depth view never stands on the geometry of the last time
// (the world may have moved since): its fixed surface until new geometry comes.
// `omniview render --cloud` given what the daemon stood the view on (the rig, one frame set's
// camera images as the robot sent them, the lidar cloud that came with them: all from
// StreamSourceFrames, as a recording keeps them) makes the daemon's picture: the offline
// tool and the served view are one code path. The daemon's geometry also holds the depth
// cameras' points and the previous rotations, and its frame another frame set's images, so
// "the same" is within a few grey levels, far closer than the fixed surface's picture.
TEST_F(DepthViews, OfflineRenderWithTheSameCloudGivesTheDaemonsPicture) {
  LatestFrame fixed(*stub_, "fixed");
  LatestFrame measured(*stub_, "measured");
  v1::Frame served;
  ASSERT_TRUE(eventually_within([&] { return (served = measured.get()).measured_depth() > 0.2 && fixed.count() > 0; }, 30s))
      << "measured_depth " << served.measured_depth() << "\n" << daemon_->log();

  // One frame set with its cloud (a depth view watched makes the source pull clouds).
  auto context = make_context("", 60s);
  auto reader = stub_->StreamSourceFrames(context.get(), v1::StreamSourceFramesRequest());
  std::string rig_yaml;
  v1::SourceFrame with_cloud;
  v1::SourceFrame f;
  while (reader->Read(&f)) {
    if (!f.rig_yaml().empty()) rig_yaml = f.rig_yaml();
    if (!f.cloud_pcd().empty() && !rig_yaml.empty()) {
      with_cloud = f;
      break;
    }
  }
  context->TryCancel();
  reader->Finish();
  ASSERT_FALSE(with_cloud.cloud_pcd().empty()) << "no frame set with a cloud";
  ASSERT_GE(with_cloud.images_size(), 2);

  // The inputs as files, the view as the daemon describes it, and the command line.
  const std::filesystem::path in = dir_.path() / "offline";
  std::filesystem::create_directories(in);
  std::ostringstream command;
  command << OMNIVIEW_CLI << " render --rig " << dir_.write("offline/rig.yaml", rig_yaml);
  for (const auto& image : with_cloud.images()) {
    const std::string file = "offline/" + image.camera() + (image.encoding() == v1::JPEG ? ".jpg" : ".png");
    command << " --image " << image.camera() << "=" << dir_.write(file, image.data());
  }
  v1::GetViewRequest get;
  get.set_name("measured");
  v1::View described;
  ASSERT_TRUE(stub_->GetView(make_context().get(), get, &described).ok());
  command << " --view " << dir_.write("offline/measured.yaml", described.yaml())
          << " --cloud " << dir_.write("offline/scan.pcd", with_cloud.cloud_pcd()) << " --grey --out "
          << (in / "measured.png").string() << " 2>&1";
  const ProcessResult run = run_process(command.str());
  ASSERT_EQ(run.exit_code, 0) << command.str() << "\n" << run.output;
  const cv::Mat offline = read_image((in / "measured.png").string(), ImageColour::kGrey);
  ASSERT_EQ(offline.cols, served.width());
  ASSERT_EQ(offline.rows, served.height());

  // Grey levels over the pixels both paint, and the pixels one paints and the other not.
  const auto compare = [&](const v1::Frame& frame, size_t* one_only) {
    const cv::Mat image(frame.height(), frame.width(), CV_8UC1, const_cast<char*>(frame.data().data()));
    double error = 0;
    size_t n = 0, differ = 0;
    for (int v = 0; v < image.rows; ++v) {
      for (int u = 0; u < image.cols; ++u) {
        const int a = image.at<uint8_t>(v, u), b = offline.at<uint8_t>(v, u);
        if ((a == 0) != (b == 0)) ++differ;
        if (a == 0 || b == 0) continue;
        error += double(a - b) * double(a - b);
        ++n;
      }
    }
    if (one_only) *one_only = differ;
    return n == 0 ? 0.0 : 10 * std::log10(255.0 * 255.0 / std::max(error / double(n), 1e-9));
  };
  // Compared: the newest frame that says it stood on measured depth. The newest frame may
  // have been made on the fixed surface while the lidar was quiet past the geometry's
  // freshness (CI's ASan run read such a frame here: its picture was the fixed view's).
  ASSERT_TRUE(eventually_within([&] { return (served = measured.get()).measured_depth() > 0.2; }, 30s))
      << "measured_depth of the newest frame " << served.measured_depth() << "\n" << daemon_->log();
  size_t differ = 0;
  const double db_served = compare(served, &differ), db_fixed = compare(fixed.get(), nullptr);
  std::cout << "offline render against the daemon's measured view (" << 100 * served.measured_depth()
            << " % on measured depth): " << db_served << " dB, " << differ
            << " px painted by one only; against its fixed view: " << db_fixed << " dB\n";
  EXPECT_GT(db_served, 35);
  EXPECT_GT(db_served, db_fixed + 6);
  EXPECT_LT(differ, size_t(0.01 * served.width() * served.height()));
}

TEST_F(DepthViews, AViewWatchedAgainDropsItsOldGeometry) {
  {
    LatestFrame measured(*stub_, "measured");
    ASSERT_TRUE(eventually_within([&] { return measured.get().measured_depth() > 0.2; }, 30s)) << daemon_->log();
  }
  std::this_thread::sleep_for(4s);
  // Unwatched, the view keeps the geometry of the last time (at least 4 s old now) or none
  // at all (-1): the lidar may have gone quiet past kFreshGeometry before the stream's end
  // reached the daemon (a sanitizer build's GetImage deadlines), or a new rig rebuilt the
  // map meanwhile. Never fresh geometry: nobody asks for it.
  const v1::ViewStatus unwatched = view_status("measured");
  const double unwatched_age = unwatched.depth_geometry_age_s();
  EXPECT_TRUE(unwatched_age < 0 || unwatched_age >= 4) << "geometry " << unwatched_age << " s old, unwatched";
  EXPECT_NE(unwatched.depth_message().find("not watched"), std::string::npos) << unwatched.depth_message();
  EXPECT_EQ(unwatched.measured_depth(), 0) << "a watcher would start on the fixed surface";
  const auto watched_again = std::chrono::steady_clock::now();
  LatestFrame again(*stub_, "measured");
  ASSERT_TRUE(eventually_within([&] { return again.count() > 0; }, 20s));
  // No geometry yet (-1), or geometry that came after the view was watched again (its first
  // frame may take seconds in a sanitizer build, and new clouds come meanwhile).
  const v1::ViewStatus watched = view_status("measured");
  const double since_watched = std::chrono::duration<double>(std::chrono::steady_clock::now() - watched_again).count();
  EXPECT_LT(watched.depth_geometry_age_s(), since_watched)
      << "the geometry of the last time someone watched (watched again " << since_watched << " s ago)";
  ASSERT_TRUE(eventually_within([&] { return again.get().measured_depth() > 0.2; }, 30s));
}

TEST_F(DepthViews, AViewChangedKeepsStandingOnMeasuredDepth) {
  LatestFrame measured(*stub_, "measured");
  ASSERT_TRUE(eventually_within([&] { return measured.get().measured_depth() > 0.2; }, 30s)) << daemon_->log();
  // A pan (a joystick step): the new revision's first frame already stands on the geometry.
  v1::UpdateViewRequest r;
  r.set_name("measured");
  r.mutable_delta()->set_yaw_deg(10);
  v1::View updated;
  ASSERT_TRUE(stub_->UpdateView(make_context().get(), r, &updated).ok());
  ASSERT_TRUE(eventually_within([&] { return measured.get().camera().revision() == updated.revision(); }, 10s));
  // Under a sanitizer the source can stall for seconds (GetImage deadlines; an ASan
  // rehearsal of stop 36): geometry older than 2 s is not used, so the new revision starts
  // on its fixed surface until clouds come again, as on a robot whose lidar went quiet.
  if (test_time_scale() == 1) {
    EXPECT_GT(measured.get().measured_depth(), 0.2);
  }
  EXPECT_TRUE(eventually_within(
      [&] {
        const v1::Frame f = measured.get();
        return f.camera().revision() == updated.revision() && f.measured_depth() > 0.2;
      },
      30s))
      << daemon_->log();
  // And back to fixed: no measured depth, no geometry.
  v1::UpdateViewRequest fixed;
  fixed.set_name("measured");
  fixed.mutable_set()->set_depth(v1::FIXED);
  ASSERT_TRUE(stub_->UpdateView(make_context().get(), fixed, &updated).ok());
  EXPECT_EQ(updated.spec().depth(), v1::FIXED);
  ASSERT_TRUE(eventually_within([&] { return measured.get().camera().revision() == updated.revision(); }, 10s));
  EXPECT_EQ(measured.get().measured_depth(), 0);
  EXPECT_EQ(view_status("measured").depth_message(), "");
}

TEST_F(DepthViews, ViewsTooLargeForDepthAreRefusedNamingTheLimit) {
  v1::CreateViewRequest r;
  *r.mutable_spec() = front_view("huge", v1::MEASURED);
  r.mutable_spec()->set_width(2100);  // just over 2048x1024
  r.mutable_spec()->set_height(1000);
  v1::View created;
  const grpc::Status s = stub_->CreateView(make_context().get(), r, &created);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(s.error_message().find("depth: measured takes views of at most"), std::string::npos) << s.error_message();
  r.mutable_spec()->set_depth(v1::FIXED);
  // The same size with a fixed surface is fine (its map build takes seconds under a sanitizer).
  EXPECT_TRUE(stub_->CreateView(make_context("", time_scaled(std::chrono::seconds(20))).get(), r, &created).ok());
}

}  // namespace
}  // namespace omniview::testing
