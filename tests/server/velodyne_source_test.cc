// `type: velodyne` end to end: VLP-16 packets made from the synthetic room, sent over real
// UDP on loopback to the real omniviewd, whose rotations come back through StreamClouds
// (real gRPC) coloured from the camera source the velodyne source holds.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <map>
#include <sstream>
#include <thread>

#include "cloud_scene.h"
#include "core/io/image_codec.h"
#include "core/synthetic/spot_like_rig.h"
#include "tests/server/daemon_process.h"
#include "vlp16_packets.h"

namespace omniview::testing {
namespace {

using namespace std::chrono_literals;

std::chrono::milliseconds scaled(std::chrono::milliseconds t) {
  return std::chrono::milliseconds(static_cast<int64_t>(t.count() * test_time_scale()));
}

// A UDP port free on loopback right now (the daemon binds it a moment later).
int free_udp_port() {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t n = sizeof a;
  getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
  close(fd);
  return ntohs(a.sin_port);
}

// Sends the packets of a lidar at T_world_lidar spinning on and on to 127.0.0.1:port at
// about the sensor's pace (each made as it goes: whole rotations, azimuth ever advancing),
// until stopped.
class PacketSender {
 public:
  PacketSender(const synthetic::Scene& scene, const Pose& T_world_lidar, int port) {
    fd_ = socket(AF_INET, SOCK_DGRAM, 0);
    to_.sin_family = AF_INET;
    to_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    to_.sin_port = htons(static_cast<uint16_t>(port));
    thread_ = std::thread([this, &scene, T_world_lidar] {
      for (int k = 0; !stop_; ++k) {
        send(test::vlp16_packets(scene, T_world_lidar, 1, 12 * k).front());
        std::this_thread::sleep_for(1300us);  // ~754 packets/s: a VLP-16 at 10 Hz
      }
    });
  }
  ~PacketSender() {
    stop_ = true;
    thread_.join();
    close(fd_);
  }
  void send(const std::vector<uint8_t>& p) {
    sendto(fd_, p.data(), p.size(), 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_);
  }

 private:
  int fd_ = -1;
  sockaddr_in to_{};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

struct Point {
  Vec3 p;
  uint8_t r = 0, g = 0, b = 0, flags = 0;
};

// Decodes the packed points by the message's own field list (x y z float32, r g b flags uint8).
std::vector<Point> decode(const v1::PointCloud& c) {
  std::map<std::string, const v1::PointField*> f;
  for (const auto& field : c.fields()) f[field.name()] = &field;
  for (const char* name : {"x", "y", "z", "r", "g", "b", "flags"}) {
    EXPECT_TRUE(f.count(name)) << name;
    if (!f.count(name)) return {};
  }
  std::vector<Point> out(c.point_count());
  for (size_t i = 0; i < out.size(); ++i) {
    const char* at = c.data().data() + i * c.point_stride();
    float xyz[3];
    for (int k = 0; k < 3; ++k) std::memcpy(&xyz[k], at + f[std::string(1, "xyz"[k])]->offset(), 4);
    out[i].p = Vec3(xyz[0], xyz[1], xyz[2]);
    out[i].r = static_cast<uint8_t>(at[f["r"]->offset()]);
    out[i].g = static_cast<uint8_t>(at[f["g"]->offset()]);
    out[i].b = static_cast<uint8_t>(at[f["b"]->offset()]);
    out[i].flags = static_cast<uint8_t>(at[f["flags"]->offset()]);
  }
  return out;
}

// Distance of a world point to the room's nearest wall, floor or ceiling.
double off_surface(const Vec3& p) {
  return std::min(
      {std::abs(std::abs(p.x()) - 4.5), std::abs(std::abs(p.y()) - 3.5), std::abs(p.z()), std::abs(p.z() - 3.0)});
}

class VelodyneSource : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto rig = synthetic::spot_like_rig();
    save_rig_yaml(rig, (dir_.path() / "rig.yaml").string());
    const auto images = test::render_images(scene_, *test::rig_in_world(T_world_body_));
    std::ostringstream yaml;
    for (size_t i = 0; i < images.size(); ++i) {
      const std::string name = rig.cameras()[i].name;
      write_image(dir_.path() / (name + ".png"), images[i]);
      yaml << (i ? ", " : "") << name << ": " << name << ".png";
    }
    port_ = free_udp_port();
    before_daemon();
    const Pose& T = test::T_body_lidar();
    std::ostringstream config;
    config << "listen: 127.0.0.1:0\nsources:\n"
           << "  - name: rig\n    type: velodyne\n"
           << "    cameras: {type: images, rig: rig.yaml, rate_hz: 20, images: {" << yaml.str() << "}}\n"
           << "    port: " << port_ << "\n    frame: lidar\n    parent: body\n"
           << "    pose: [" << T.translation().x() << ", " << T.translation().y() << ", " << T.translation().z()
           << ", 0, 0, 0]\n"
           << extra_keys();
    daemon_ = std::make_unique<DaemonProcess>(dir_, config.str());
    stub_ = make_stub(daemon_->address());
  }

  virtual void before_daemon() {}
  virtual std::string extra_keys() const { return ""; }  // more of the source's keys

  synthetic::Scene scene_ = test::textured_room();
  Pose T_world_body_ = make_pose(Vec3(0.3, -0.2, 0.55), 0.4, 0, 0);
  TempDir dir_;
  int port_ = 0;
  std::unique_ptr<DaemonProcess> daemon_;
  std::unique_ptr<v1::Omniview::Stub> stub_;
};

TEST_F(VelodyneSource, RotationsOverUdpComeBackColouredOnTheScene) {
  const Pose T_world_lidar = T_world_body_ * test::T_body_lidar();
  PacketSender sender(scene_, T_world_lidar, port_);

  v1::StreamCloudsRequest request;
  request.set_source("rig");
  request.mutable_options()->set_frame("body");
  auto ctx = make_context("", scaled(10s));
  auto reader = stub_->StreamClouds(ctx.get(), request);
  v1::PointCloud cloud;
  // Whole rotations only, the first too (decoding began mid-sweep: that part is dropped).
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(reader->Read(&cloud)) << reader->Finish().error_message();
    ASSERT_GT(cloud.point_count(), 27000u) << "a VLP-16 rotation in a closed room has ~28.9 k returns";
  }
  ctx->TryCancel();
  const auto points = decode(cloud);

  size_t on_surface = 0, coloured = 0, right_colour = 0;
  for (const auto& pt : points) {
    const Vec3 p_world = T_world_body_ * pt.p;
    on_surface += off_surface(p_world) < 0.01;
    if (!(pt.flags & 1)) continue;
    ++coloured;
    // The texture's colour where the lidar's ray meets the room.
    const Vec3 origin = T_world_lidar.translation();
    const auto hit = scene_.intersect(origin, p_world - origin);
    if (!hit) continue;
    const Vec3 bgr = scene_.colour(*hit);
    const double expected = 0.299 * bgr[2] + 0.587 * bgr[1] + 0.114 * bgr[0];
    right_colour += std::abs(test::luma({pt.r, pt.g, pt.b}) - expected) <= 8;
  }
  EXPECT_GT(on_surface, points.size() * 999 / 1000) << on_surface << " of " << points.size();
  EXPECT_GT(coloured, points.size() / 4) << coloured << " of " << points.size() << " coloured";
  EXPECT_GE(right_colour, coloured * 99 / 100) << right_colour << " of " << coloured << " within 8 grey levels";
  std::cout << points.size() << " points, " << coloured << " coloured, " << right_colour << " within 8 grey levels\n";
}

TEST_F(VelodyneSource, BadPacketsAreCountedAndSkipped) {
  const Pose T_world_lidar = T_world_body_ * test::T_body_lidar();
  const auto packets = test::vlp16_packets(scene_, T_world_lidar, 4);
  PacketSender sender(scene_, T_world_lidar, port_);
  v1::StreamCloudsRequest request;
  request.set_source("rig");
  auto ctx = make_context("", scaled(10s));
  auto reader = stub_->StreamClouds(ctx.get(), request);
  v1::PointCloud cloud;
  ASSERT_TRUE(reader->Read(&cloud)) << reader->Finish().error_message();  // decoding now
  auto broken = packets[3];
  broken[500] = 0x00;  // block 5's flag
  sender.send(std::vector<uint8_t>(100, 0xFF));
  sender.send(broken);
  ASSERT_TRUE(reader->Read(&cloud)) << "clouds keep coming after bad packets";
  v1::Status status;
  for (auto until = std::chrono::steady_clock::now() + scaled(3s); std::chrono::steady_clock::now() < until;) {
    auto c = make_context();
    ASSERT_TRUE(stub_->GetStatus(c.get(), v1::GetStatusRequest(), &status).ok());
    if (status.sources(0).errors() >= 2) break;
    std::this_thread::sleep_for(50ms);
  }
  EXPECT_GE(status.sources(0).errors(), 2u);
  EXPECT_NE(status.sources(0).message().find("packets skipped"), std::string::npos) << status.sources(0).message();
  // The test's packets are stamped from the top of the hour, as a lidar without GPS counts
  // from power-on: status says their times are moved onto ours (unless this runs in the
  // first or last minute of an hour, when they happen to agree).
  const auto past_hour = std::chrono::system_clock::now() - floor<std::chrono::hours>(std::chrono::system_clock::now());
  if (past_hour > 1min && past_hour < 59min) {
    EXPECT_NE(status.sources(0).message().find("lidar clock free-running"), std::string::npos)
        << status.sources(0).message();
  }
  EXPECT_EQ(status.sources(0).type(), "velodyne");
  ctx->TryCancel();
}

TEST(VelodyneConfig, ErrorsNameTheKey) {
  TempDir dir;
  const auto check = [&](const std::string& keys, const std::string& expected) {
    const std::string config = dir.write("bad.yaml",
                                         "listen: 127.0.0.1:0\nsources:\n  - name: rig\n    type: velodyne\n"
                                         "    cameras: {type: images, rig: " +
                                             example_dir() + "/rig.yaml, images: {}}\n" + keys);
    const auto r = run_process(std::string(OMNIVIEWD) + " --check --config " + config);
    EXPECT_NE(r.exit_code, 0) << keys;
    EXPECT_NE(r.output.find(expected), std::string::npos) << keys << "\n" << r.output;
  };
  check("    returns: both\n", "sources[0].returns");
  check("    port: 70000\n", "sources[0].port");
  check("    calibration: {elevation_deg: [1, 2]}\n", "sources[0].calibration.elevation_deg");
}

// The port is taken when the daemon starts (another program, or the lidar's interface not
// up yet): the daemon starts anyway, says why in status, and listens once it can.
class VelodyneBusyPort : public VelodyneSource {
 protected:
  void before_daemon() override {
    squatter_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);  // not inherited by the daemon
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<uint16_t>(port_));
    ASSERT_EQ(bind(squatter_, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  }
  void TearDown() override {
    if (squatter_ >= 0) close(squatter_);
  }
  int squatter_ = -1;
};

TEST_F(VelodyneBusyPort, ListensOnceThePortIsFree) {
  v1::Status status;
  auto c = make_context();
  ASSERT_TRUE(stub_->GetStatus(c.get(), v1::GetStatusRequest(), &status).ok());
  for (auto until = std::chrono::steady_clock::now() + scaled(3s);
       status.sources(0).message().find("cannot listen") == std::string::npos &&
       std::chrono::steady_clock::now() < until;) {
    std::this_thread::sleep_for(50ms);
    auto again = make_context();
    ASSERT_TRUE(stub_->GetStatus(again.get(), v1::GetStatusRequest(), &status).ok());
  }
  EXPECT_NE(status.sources(0).message().find("cannot listen"), std::string::npos) << status.sources(0).message();
  close(squatter_);
  squatter_ = -1;
  PacketSender sender(scene_, T_world_body_ * test::T_body_lidar(), port_);
  v1::StreamCloudsRequest request;
  request.set_source("rig");
  auto ctx = make_context("", scaled(10s));
  auto reader = stub_->StreamClouds(ctx.get(), request);
  v1::PointCloud cloud;
  ASSERT_TRUE(reader->Read(&cloud)) << reader->Finish().error_message();
  EXPECT_GT(cloud.point_count(), 27000u);
  ctx->TryCancel();
}

// `sender`: packets from any other address are counted and skipped, never decoded.
class VelodyneOtherSender : public VelodyneSource {
 protected:
  std::string extra_keys() const override { return "    sender: 127.0.0.2\n"; }
};

TEST_F(VelodyneOtherSender, PacketsFromElsewhereAreRefused) {
  PacketSender sender(scene_, T_world_body_ * test::T_body_lidar(), port_);  // from 127.0.0.1
  v1::StreamCloudsRequest request;
  request.set_source("rig");
  auto ctx = make_context("", scaled(1500ms));
  auto reader = stub_->StreamClouds(ctx.get(), request);
  v1::PointCloud cloud;
  EXPECT_FALSE(reader->Read(&cloud)) << "a cloud from packets of the wrong sender";
  v1::Status status;
  auto c = make_context();
  ASSERT_TRUE(stub_->GetStatus(c.get(), v1::GetStatusRequest(), &status).ok());
  EXPECT_GT(status.sources(0).errors(), 20u);
  EXPECT_NE(status.sources(0).message().find("not from the lidar's address 127.0.0.2"), std::string::npos)
      << status.sources(0).message();
}

}  // namespace
}  // namespace omniview::testing
