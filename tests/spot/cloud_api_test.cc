// Coloured clouds end to end: spot-mock (its test scene, colour cameras, lidar) and the
// real omniviewd on loopback ports, read through GetCloud and StreamClouds by real gRPC
// clients that decode the packed points with nothing but each message's field list.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "core/camera/camera_model.h"
#include "core/cloud/cloud_file.h"
#include "spot_adapter/mock/world/mock_scene.h"
#include "tests/server/daemon_process.h"
#include "tests/spot_mock/spot_mock_process.h"

namespace omniview::testing {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// A point as the test reads it back.
struct Point {
  Vec3 p;
  uint8_t r = 0, g = 0, b = 0, flags = 0, camera = 255;
};

// Reads field `name` of point `i` as a double, by the message's own description.
double field_value(const v1::PointCloud& c, const v1::PointField& f, size_t i) {
  const char* at = c.data().data() + i * c.point_stride() + f.offset();
  switch (f.datatype()) {
    case v1::PointField::FLOAT32: {
      float v;
      std::memcpy(&v, at, 4);
      return v;
    }
    case v1::PointField::FLOAT64: {
      double v;
      std::memcpy(&v, at, 8);
      return v;
    }
    case v1::PointField::UINT8:
      return static_cast<uint8_t>(*at);
    case v1::PointField::UINT16: {
      uint16_t v;
      std::memcpy(&v, at, 2);
      return v;
    }
    default:
      ADD_FAILURE() << "field " << f.name() << " has a datatype this test does not read: " << f.datatype();
      return 0;
  }
}

std::vector<Point> decode(const v1::PointCloud& c) {
  std::map<std::string, const v1::PointField*> by_name;
  for (const auto& f : c.fields()) by_name[f.name()] = &f;
  for (const char* name : {"x", "y", "z", "r", "g", "b", "flags", "camera"}) {
    EXPECT_TRUE(by_name.count(name)) << "no field " << name;
    if (!by_name.count(name)) return {};
  }
  EXPECT_EQ(c.data().size(), size_t(c.point_count()) * c.point_stride());
  std::vector<Point> out(c.point_count());
  for (size_t i = 0; i < out.size(); ++i) {
    const auto get = [&](const char* n) { return field_value(c, *by_name[n], i); };
    out[i].p = Vec3(get("x"), get("y"), get("z"));
    out[i].r = static_cast<uint8_t>(get("r"));
    out[i].g = static_cast<uint8_t>(get("g"));
    out[i].b = static_cast<uint8_t>(get("b"));
    out[i].flags = static_cast<uint8_t>(get("flags"));
    out[i].camera = static_cast<uint8_t>(get("camera"));
  }
  return out;
}

const char* kTokens = "tokens:\n"
                      "  - {role: viewer, token: viewer-secret-123}\n"
                      "  - {role: operator, token: operator-secret-456}\n";
const char* kViewer = "viewer-secret-123";

// spot-mock (test scene, colour cameras) and omniviewd with its `spot` source, plus an
// images source without a lidar; tokens required.
class CloudApi : public ::testing::Test {
 protected:
  void SetUp() override {
    mock_ = std::make_unique<SpotMockProcess>(dir_.path(), std::vector<std::string>{"--scene", "test", "--rgb",
                                                                                    "--supersample", "1"});
    std::ostringstream config;
    config << "listen: 127.0.0.1:0\n"
           << kTokens << "sources:\n"
           << "  - name: spot\n"
           << "    type: spot\n"
           << "    robot: 127.0.0.1:" << mock_->port() << "\n"
           << "    ca_file: " << mock_->certs_dir() << "/ca.pem\n"
           << "    credentials_file: " << mock_->credentials_file() << "\n"
           << "    pixel_format: rgb\n"
           << "    rate_hz: 15\n"
           << "  - name: examples\n"
           << "    type: images\n"
           << "    rig: " << example_dir() << "/rig.yaml\n"
           << "    images: {front: " << example_dir() << "/front.jpg, back: " << example_dir() << "/back.jpg}\n"
           << "    rate_hz: 5\n"
           << extra_config();
    daemon_ = std::make_unique<DaemonProcess>(dir_, config.str());
    stub_ = make_stub(daemon_->address());
    ASSERT_TRUE(eventually_within([&] { return connected(); }, 15s)) << daemon_->log();
  }

  // More of the daemon's config (YAML at the top level).
  virtual std::string extra_config() const { return ""; }

  bool connected() {
    v1::Status st;
    if (!stub_->GetStatus(make_context(kViewer).get(), v1::GetStatusRequest(), &st).ok()) return false;
    for (const auto& s : st.sources()) {
      if (s.name() == "spot") return s.connected();
    }
    return false;
  }

  grpc::Status get_cloud(const v1::GetCloudRequest& r, v1::PointCloud& out, const std::string& token = kViewer) {
    return stub_->GetCloud(make_context(token, time_scaled(20s)).get(), r, &out);
  }

  static v1::GetCloudRequest request(const std::string& frame) {
    v1::GetCloudRequest r;
    r.set_source("spot");
    r.mutable_options()->set_frame(frame);
    r.set_timeout_ms(static_cast<int>(std::min(60000.0, 10000 * test_time_scale())));
    return r;
  }

  TempDir dir_;
  std::unique_ptr<SpotMockProcess> mock_;
  std::unique_ptr<DaemonProcess> daemon_;
  std::unique_ptr<v1::Omniview::Stub> stub_;
};

// Which of the mock's cameras see `p_world` (in its image, and nothing of the scene in
// front of it): the mock's own world, not the daemon's idea of it.
bool mock_camera_sees(const synthetic::Scene& scene, const Rig& rig, const Vec3& p_world) {
  for (size_t i = 0; i < rig.cameras().size(); ++i) {
    const Camera& cam = rig.cameras()[i];
    const Pose T_world_cam = rig.camera_pose(spot_mock::kWorldFrame, i);
    Vec2 uv;
    // A margin inside the image: the colourer's usable region ends where bilinear reads would.
    if (!project(cam.model, T_world_cam.inverse() * p_world, uv) || uv.x() < 2 || uv.y() < 2 ||
        uv.x() > cam.width - 3 || uv.y() > cam.height - 3) {
      continue;
    }
    const Vec3 origin = T_world_cam.translation();
    const auto hit = scene.intersect(origin, p_world - origin);
    if (hit && hit->t > 1 - 1e-3) return true;
  }
  return false;
}

TEST_F(CloudApi, CloudIsInTheRequestedFrameAndColouredLikeTheMocksScene) {
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(mock_->counter("get_point_cloud_calls"), 0) << "a cloud was pulled with nobody watching";

  v1::PointCloud cloud;
  const grpc::Status s = get_cloud(request(spot_mock::kWorldFrame), cloud);
  ASSERT_TRUE(s.ok()) << s.error_message() << "\n" << daemon_->log();
  EXPECT_EQ(cloud.frame(), spot_mock::kWorldFrame);
  EXPECT_EQ(cloud.source(), "spot");
  EXPECT_EQ(cloud.cameras_size(), 5);
  const auto points = decode(cloud);
  ASSERT_GT(points.size(), 5000u);
  EXPECT_EQ(cloud.counts().points(), points.size());
  EXPECT_EQ(cloud.counts().coloured() + cloud.counts().occluded() + cloud.counts().self_filtered() +
                cloud.counts().unseen(),
            points.size());
  std::cout << "cloud: " << points.size() << " points, " << cloud.data().size() << " bytes, coloured in "
            << cloud.colour_ms() << " ms, latency " << cloud.latency_ms() << " ms\n";

  // In "vision" the test scene is the floor z = 0 and the wall x = 3: every point lies on one.
  size_t on_surface = 0;
  for (const auto& pt : points) {
    if (std::abs(pt.p.z()) < 0.02 || std::abs(pt.p.x() - spot_mock::kTestWallX) < 0.02) ++on_surface;
  }
  EXPECT_EQ(on_surface, points.size()) << "points off the scene's surfaces: the frame transform is wrong";

  // Of the points some mock camera sees, >= 90 % are coloured, and their colours are the
  // scene's texture there. Within 4 m of the body every camera resolves the texture; farther
  // out the floor is seen at a grazing angle, where one camera pixel spans more of the busy
  // texture than a lidar point does (measured: 99 % within 24 levels up to 4 m, 46 % at
  // 6-10 m, with no bias), so colours are compared up close and their bias everywhere.
  const synthetic::Scene scene = spot_mock::make_scene(spot_mock::SceneKind::kTest);
  const Rig rig = spot_mock::mock_rig();
  const Vec3 body(0, 0, spot_mock::kBodyHeightM);
  size_t seen = 0, coloured = 0, near = 0, agree = 0;
  Vec3 bias = Vec3::Zero();
  for (const auto& pt : points) {
    if (!mock_camera_sees(scene, rig, pt.p)) continue;
    ++seen;
    if (!(pt.flags & 1)) continue;
    ++coloured;
    EXPECT_LT(pt.camera, 5) << "a coloured point names no camera";
    const Vec3 bgr = synthetic::Scene::texture(pt.p);
    const Vec3 error(pt.r - bgr[2], pt.g - bgr[1], pt.b - bgr[0]);
    bias += error;
    if ((pt.p - body).norm() > 4) continue;
    ++near;
    if (error.cwiseAbs().maxCoeff() <= 24) ++agree;
  }
  bias /= std::max<size_t>(coloured, 1);
  std::cout << "seen " << seen << ", coloured " << coloured << "; within 4 m " << near << ", of them within 24 levels "
            << agree << "; mean error (r g b) " << bias.transpose() << "\n";
  ASSERT_GT(seen, 3000u);
  EXPECT_GE(coloured, 0.9 * seen);
  ASSERT_GT(near, 2000u);
  EXPECT_GE(agree, 0.95 * near);
  EXPECT_LT(bias.cwiseAbs().maxCoeff(), 4) << "colours are biased (a channel swapped, or a camera's pose wrong)";

  // The same cloud in the body frame: the floor is kBodyHeightM below.
  v1::PointCloud in_body;
  ASSERT_TRUE(get_cloud(request("body"), in_body).ok());
  EXPECT_EQ(in_body.frame(), "body");
  size_t floor_points = 0;
  for (const auto& pt : decode(in_body)) floor_points += std::abs(pt.p.z() + spot_mock::kBodyHeightM) < 0.02;
  EXPECT_GT(floor_points, in_body.point_count() / 2);
}

TEST_F(CloudApi, VoxelThinsAndCropKeepsOnlyInsidePoints) {
  v1::PointCloud full;
  ASSERT_TRUE(get_cloud(request("body"), full).ok()) << daemon_->log();
  auto thin_request = request("body");
  thin_request.mutable_options()->set_voxel_size_m(0.25);
  v1::PointCloud thin;
  ASSERT_TRUE(get_cloud(thin_request, thin).ok());
  EXPECT_LT(thin.point_count(), full.point_count() / 2);
  EXPECT_GT(thin.point_count(), 100u);
  EXPECT_EQ(thin.input_points(), full.input_points());
  // One point per voxel: no two closer than a voxel's cells allow is too strict for means,
  // but no two may share a cell's mean exactly.
  const auto thin_points = decode(thin);
  size_t thin_coloured = 0;
  for (const auto& p : thin_points) thin_coloured += p.flags & 1;
  EXPECT_GT(thin_coloured, thin_points.size() / 2) << "voxels keep their colours";

  auto crop_request = request("body");
  auto* crop = crop_request.mutable_options()->mutable_crop();
  crop->mutable_min()->set_x(0.5);
  crop->mutable_min()->set_y(-1);
  crop->mutable_min()->set_z(-1);
  crop->mutable_max()->set_x(4);
  crop->mutable_max()->set_y(1);
  crop->mutable_max()->set_z(1);
  v1::PointCloud cropped;
  ASSERT_TRUE(get_cloud(crop_request, cropped).ok());
  const auto inside = decode(cropped);
  ASSERT_GT(inside.size(), 50u);
  EXPECT_LT(inside.size(), full.point_count() / 2);
  for (const auto& pt : inside) {
    ASSERT_TRUE(pt.p.x() >= 0.5 - 1e-4 && pt.p.x() <= 4 + 1e-4 && std::abs(pt.p.y()) <= 1 + 1e-4 &&
                std::abs(pt.p.z()) <= 1 + 1e-4)
        << pt.p.transpose();
  }
  // Every point of the full cloud inside the box is in the cropped one (same static scene).
  size_t expected = 0;
  for (const auto& pt : decode(full)) {
    expected += pt.p.x() >= 0.5 && pt.p.x() <= 4 && std::abs(pt.p.y()) <= 1 && std::abs(pt.p.z()) <= 1;
  }
  EXPECT_NEAR(double(inside.size()), double(expected), 0.01 * expected + 2);
}

TEST_F(CloudApi, ViewersReadAndBadRequestsGetClearErrors) {
  v1::PointCloud out;
  EXPECT_TRUE(get_cloud(request(""), out).ok());
  EXPECT_EQ(get_cloud(request(""), out, "").error_code(), grpc::StatusCode::UNAUTHENTICATED);

  const auto refused = [&](v1::GetCloudRequest r, grpc::StatusCode code, const std::string& words) {
    const grpc::Status s = get_cloud(r, out);
    EXPECT_EQ(s.error_code(), code) << s.error_message();
    EXPECT_NE(s.error_message().find(words), std::string::npos) << s.error_message();
  };
  auto r = request("");
  r.mutable_options()->set_voxel_size_m(-1);
  refused(r, grpc::StatusCode::INVALID_ARGUMENT, "options.voxel_size_m");
  r.mutable_options()->set_voxel_size_m(0.001);
  refused(r, grpc::StatusCode::INVALID_ARGUMENT, "options.voxel_size_m");
  r.mutable_options()->set_voxel_size_m(std::nan(""));
  refused(r, grpc::StatusCode::INVALID_ARGUMENT, "options.voxel_size_m");
  r = request("");
  r.mutable_options()->mutable_crop()->mutable_min()->set_x(2);
  r.mutable_options()->mutable_crop()->mutable_max()->set_x(1);
  refused(r, grpc::StatusCode::INVALID_ARGUMENT, "options.crop");
  r = request("");
  r.mutable_options()->mutable_crop()->mutable_max()->set_z(INFINITY);
  refused(r, grpc::StatusCode::INVALID_ARGUMENT, "options.crop.max.z");
  r = request("no_such_frame");
  refused(r, grpc::StatusCode::INVALID_ARGUMENT, "no_such_frame");
  r = request("");
  r.set_timeout_ms(70000);
  refused(r, grpc::StatusCode::INVALID_ARGUMENT, "timeout_ms");
  r = request("");
  r.set_source("nowhere");
  refused(r, grpc::StatusCode::NOT_FOUND, "nowhere");
  r.set_source("examples");
  refused(r, grpc::StatusCode::FAILED_PRECONDITION, "examples");

  v1::StreamCloudsRequest stream;
  stream.set_source("spot");
  stream.set_max_rate_hz(-2);
  auto ctx = make_context(kViewer);
  auto reader = stub_->StreamClouds(ctx.get(), stream);
  v1::PointCloud c;
  EXPECT_FALSE(reader->Read(&c));
  const grpc::Status s = reader->Finish();
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(s.error_message().find("max_rate_hz"), std::string::npos) << s.error_message();
}

// Reads a cloud stream on its own thread; `stall` opens it and never reads.
class CloudReader {
 public:
  CloudReader(v1::Omniview::Stub& stub, double rate_hz, bool stall) {
    context_ = make_context(kViewer, 120s);
    v1::StreamCloudsRequest r;
    r.set_source("spot");
    r.set_max_rate_hz(rate_hz);
    reader_ = stub.StreamClouds(context_.get(), r);
    if (stall) return;
    thread_ = std::thread([this] {
      v1::PointCloud c;
      while (reader_->Read(&c)) {
        std::lock_guard lock(mutex_);
        ++clouds_;
        last_sequence_ = c.sequence();
        colour_ms_ = c.colour_ms();
        bytes_ = c.ByteSizeLong();
      }
    });
  }
  ~CloudReader() {
    context_->TryCancel();
    if (thread_.joinable()) thread_.join();
  }
  size_t clouds() const {
    std::lock_guard lock(mutex_);
    return clouds_;
  }
  // The newest cloud's colouring time in the daemon and its message size.
  std::pair<double, size_t> last_cost() const {
    std::lock_guard lock(mutex_);
    return {colour_ms_, bytes_};
  }

 private:
  std::unique_ptr<grpc::ClientContext> context_;
  std::unique_ptr<grpc::ClientReader<v1::PointCloud>> reader_;
  mutable std::mutex mutex_;
  size_t clouds_ = 0;
  uint64_t last_sequence_ = 0;
  double colour_ms_ = 0;
  size_t bytes_ = 0;
  std::thread thread_;
};

TEST_F(CloudApi, AStalledClientSlowsNobodyAndCloudsStopWithTheLastWatcher) {
  double alone_rate = 0;
  {
    CloudReader reader(*stub_, 0, false);
    ASSERT_TRUE(eventually_within([&] { return reader.clouds() >= 3; }, 15s)) << daemon_->log();
    const size_t before = reader.clouds();
    std::this_thread::sleep_for(time_scaled(3s));
    alone_rate = (reader.clouds() - before) / (3 * test_time_scale());
  }
  std::cout << "clouds per second, one reader: " << alone_rate << "\n";
  ASSERT_GT(alone_rate, 0.5);
  {
    // Six stalled streams hold their slots and gRPC's buffers full; a reader beside them
    // keeps its rate.
    std::vector<std::unique_ptr<CloudReader>> stalled;
    for (int i = 0; i < 6; ++i) stalled.push_back(std::make_unique<CloudReader>(*stub_, 0, true));
    CloudReader reader(*stub_, 0, false);
    ASSERT_TRUE(eventually_within([&] { return reader.clouds() >= 3; }, 15s)) << daemon_->log();
    // The stalled streams' buffers fill up; from then on their clouds are dropped, not queued.
    const auto cloud_clients = [&](uint64_t* dropped) {
      v1::Status st;
      EXPECT_TRUE(stub_->GetStatus(make_context(kViewer).get(), v1::GetStatusRequest(), &st).ok());
      int n = 0;
      *dropped = 0;
      for (const auto& c : st.clients()) {
        if (c.view() != "cloud:spot") continue;
        ++n;
        *dropped += c.frames_dropped();
      }
      return n;
    };
    uint64_t dropped = 0;
    EXPECT_EQ(cloud_clients(&dropped), 7);
    EXPECT_TRUE(eventually_within([&] { return cloud_clients(&dropped) == 7 && dropped > 0; }, 30s))
        << "the stalled streams' clouds are dropped, not queued";
    const size_t before = reader.clouds();
    std::this_thread::sleep_for(time_scaled(3s));
    const double rate = (reader.clouds() - before) / (3 * test_time_scale());
    std::cout << "clouds per second beside 6 stalled streams: " << rate << " (" << dropped << " dropped for them)\n";
    EXPECT_GT(rate, 0.6 * alone_rate);
  }
  // Nobody watches any more: no more GetPointCloud calls (one still in flight may land).
  ASSERT_TRUE(eventually_within(
      [&] {
        v1::Status st;
        if (!stub_->GetStatus(make_context(kViewer).get(), v1::GetStatusRequest(), &st).ok()) return false;
        return std::none_of(st.clients().begin(), st.clients().end(),
                            [](const auto& c) { return c.view() == "cloud:spot"; });
      },
      10s));
  std::this_thread::sleep_for(time_scaled(500ms));
  const double calls = mock_->counter("get_point_cloud_calls");
  std::this_thread::sleep_for(time_scaled(1500ms));
  EXPECT_LE(mock_->counter("get_point_cloud_calls"), calls + 1) << "clouds pulled with nobody watching";
}

TEST_F(CloudApi, AfterNobodyWatchedTheNextCloudIsNewNotTheLastWatchersLeftover) {
  // A GetCloud leaves a request's answer behind; one asked for seconds later must not get it.
  v1::PointCloud first, later;
  ASSERT_TRUE(get_cloud(request(""), first).ok()) << daemon_->log();
  std::this_thread::sleep_for(3s);  // nobody watches: no cloud is pulled, none may be kept as news
  const auto asked = std::chrono::system_clock::now();
  ASSERT_TRUE(get_cloud(request(""), later).ok()) << daemon_->log();
  const auto stamp = std::chrono::system_clock::time_point(std::chrono::seconds(later.stamp().seconds()) +
                                                           std::chrono::nanoseconds(later.stamp().nanos()));
  const double age_s = std::chrono::duration<double>(asked - stamp).count();
  // The mock's lidar answers with a scan of its time of answering (on this machine's clock).
  EXPECT_LT(age_s, 1.0) << "captured " << age_s << " s before it was asked for (sequence " << later.sequence()
                        << ", the first cloud's " << first.sequence() << ")";
}

TEST_F(CloudApi, StreamHonoursItsRate) {
  CloudReader reader(*stub_, 2, false);
  ASSERT_TRUE(eventually_within([&] { return reader.clouds() >= 1; }, 15s)) << daemon_->log();
  const size_t before = reader.clouds();
  std::this_thread::sleep_for(3s);
  const size_t got = reader.clouds() - before;
  EXPECT_LE(got, 8u) << "max_rate_hz 2 over 3 s";
  EXPECT_GE(got, test_time_scale() > 1 ? 1u : 4u);
  const auto [colour_ms, bytes] = reader.last_cost();
  std::cout << "a streamed cloud: coloured in " << colour_ms << " ms, " << bytes << " bytes a message\n";
  EXPECT_GT(bytes, 100000u);
}

// With the robot's model (the shipped Spot-like URDF) the daemon runs the self-filter on
// every cloud, posed at the robot's reported joints. The mock's lidar sits on the body's
// top and its lowest ring (-15 deg) meets the floor about 2.3 m out, so it sees nothing of
// the robot: no point may be flagged as the robot, and the filter must not fail (core's
// tests/cloud check what it flags on a body the lidar does see).
class CloudApiWithRobot : public CloudApi {
 protected:
  std::string extra_config() const override {
    return std::string("robot_models:\n  - source: spot\n    urdf: ") + OMNIVIEW_SOURCE_DIR +
           "/config/robots/spot/spot_like.urdf\n    frame: body\n";
  }
};

TEST_F(CloudApiWithRobot, SelfFilterRunsAndFlagsNothingOffTheRobot) {
  v1::PointCloud cloud;
  const grpc::Status s = get_cloud(request("body"), cloud);
  ASSERT_TRUE(s.ok()) << s.error_message() << "\n" << daemon_->log();
  const auto points = decode(cloud);
  ASSERT_GT(points.size(), 5000u);
  double nearest = 1e9;
  for (const auto& pt : points) nearest = std::min(nearest, pt.p.head<2>().norm());
  EXPECT_GT(nearest, 1.5) << "the premise: the lidar sees nothing near the robot";
  EXPECT_EQ(cloud.counts().self_filtered(), 0u);
  EXPECT_GT(cloud.counts().coloured(), points.size() / 2);
  EXPECT_EQ(daemon_->log().find("not self-filtered"), std::string::npos) << daemon_->log();
}

// The CLI: `omniview cloud` writes binary PLY that core's reader reads back, coloured.
TEST_F(CloudApi, CliSavesColouredPlyFiles) {
  const std::string cli = std::string("OMNIVIEW_TOKEN=") + kViewer + " " + OMNIVIEW_CLI + " --server " +
                          daemon_->address() + " cloud";
  const std::string one = (dir_.path() / "one.ply").string();
  auto r = run_process(cli + " spot -o " + one + " --frame vision --wait 20");
  ASSERT_EQ(r.exit_code, 0) << r.output << "\n" << daemon_->log();
  EXPECT_NE(r.output.find("coloured "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("unseen "), std::string::npos) << r.output;
  const PointCloud cloud = load_cloud(one);
  EXPECT_EQ(cloud.frame, "vision");
  ASSERT_GT(cloud.size(), 5000u);
  ASSERT_EQ(cloud.rgb.size(), cloud.size());
  ASSERT_EQ(cloud.flags.size(), cloud.size());
  size_t coloured = 0, agree = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (!(cloud.flags[i] & 1)) continue;
    ++coloured;
    const Vec3 p = cloud.points[i].cast<double>();
    if ((p - Vec3(0, 0, spot_mock::kBodyHeightM)).norm() > 4) continue;
    const Vec3 bgr = synthetic::Scene::texture(p);
    agree += std::max({std::abs(cloud.rgb[i][0] - bgr[2]), std::abs(cloud.rgb[i][1] - bgr[1]),
                       std::abs(cloud.rgb[i][2] - bgr[0])}) <= 24;
  }
  EXPECT_GT(coloured, cloud.size() / 2);
  EXPECT_GT(agree, 2000u) << "the file's colours are the scene's";

  // Coloured points only, thinned: smaller, and every point coloured.
  const std::string thin = (dir_.path() / "thin.pcd").string();
  r = run_process(cli + " spot -o " + thin + " --voxel 0.3 --coloured-only --wait 20");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const PointCloud thinned = load_cloud(thin);
  EXPECT_LT(thinned.size(), cloud.size() / 2);
  EXPECT_GT(thinned.size(), 50u);
  for (uint8_t f : thinned.flags) ASSERT_TRUE(f & 1);

  // A stream of three, numbered.
  const std::string many = (dir_.path() / "many.ply").string();
  r = run_process(cli + " spot -o " + many + " --count 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* name : {"many_000001.ply", "many_000002.ply", "many_000003.ply"}) {
    EXPECT_GT(load_cloud((dir_.path() / name).string()).size(), 5000u) << name;
  }

  // A crop box with nothing inside: the file is written, and why it is empty is said.
  r = run_process(cli + " spot -o " + (dir_.path() / "empty.ply").string() + " --crop 50,50,50,51,51,51 --wait 20");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("holds no point: the crop box (--crop, in --frame) left none"), std::string::npos) << r.output;

  // Mistakes are named.
  r = run_process(cli + " spot -o " + one + " --voxel 0.001");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("voxel"), std::string::npos) << r.output;
  r = run_process(cli + " examples -o " + one);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("delivers no point clouds"), std::string::npos) << r.output;
  r = run_process(cli + " spot -o out.txt");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find(".ply or .pcd"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace omniview::testing
