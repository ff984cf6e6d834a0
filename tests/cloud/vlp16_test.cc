// VLP-16 decoding: the axis and azimuth conventions on a hand-made packet, full rotations
// from packets of the synthetic scene received over loopback UDP, and clear errors.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>

#include <gtest/gtest.h>

#include "cloud_scene.h"
#include "core/cloud/vlp16.h"
#include "vlp16_packets.h"

namespace omniview {
namespace {

using Clock = std::chrono::system_clock;

TEST(Vlp16, ConventionsOnAHandMadePacket) {
  std::vector<uint8_t> p(kVlp16PacketSize, 0);
  for (int b = 0; b < 12; ++b) {
    p[100 * b] = 0xFF;
    p[100 * b + 1] = 0xEE;
    test::put16(p, 100 * b + 2, static_cast<uint16_t>(9000 + 40 * b));  // 90 deg: to the right
  }
  test::put16(p, 4, 1000);  // block 0, laser 0 (-15 deg), 2 m
  p[6] = 77;
  p[1204] = 0x37;
  Vlp16Assembler assembler(Vlp16Calibration{}, "velodyne");
  const auto received = Clock::now();
  EXPECT_TRUE(assembler.add_packet(p.data(), p.size(), received).empty());
  // The next packet starts again at azimuth 0: the rotation is done.
  for (int b = 0; b < 12; ++b) test::put16(p, 100 * b + 2, static_cast<uint16_t>(40 * b));
  const auto done = assembler.add_packet(p.data(), p.size(), received);
  ASSERT_EQ(done.size(), 1u);
  const PointCloud& c = done[0];
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c.frame, "velodyne");
  EXPECT_NEAR(c.points[0].x(), 0.0, 1e-6);
  EXPECT_NEAR(c.points[0].y(), -2 * std::cos(15 * M_PI / 180), 1e-5);  // right is -y (REP-103)
  EXPECT_NEAR(c.points[0].z(), -2 * std::sin(15 * M_PI / 180), 1e-5);
  EXPECT_EQ(c.ring[0], 0);
  EXPECT_EQ(c.intensity[0], 77);
}

TEST(Vlp16, PacketTimeTakesTheNearestHour) {
  using namespace std::chrono;
  const auto hour = floor<hours>(Clock::now());
  EXPECT_EQ(vlp16_packet_time(3599999000u, hour + milliseconds(2)), hour - milliseconds(1));
  EXPECT_EQ(vlp16_packet_time(1000u, hour + milliseconds(2)), hour + milliseconds(1));
}

// Packets sent every 1.33 ms whose stamps are the sender's clock, `lidar_behind` behind
// ours, arriving 0.2-2.2 ms after they were sent.
struct SentPacket {
  uint32_t us_past_hour;
  Clock::time_point sent, received;
};
std::vector<SentPacket> packets_from(Clock::time_point start, Clock::duration lidar_behind, int count) {
  using namespace std::chrono;
  std::vector<SentPacket> out;
  for (int k = 0; k < count; ++k) {
    const auto sent = start + microseconds(1330 * k);
    const auto lidar = sent - lidar_behind;
    const auto us = duration_cast<microseconds>(lidar - floor<hours>(lidar)).count();
    out.push_back({static_cast<uint32_t>(us), sent, sent + microseconds(200 + (k * 7919) % 2000)});
  }
  return out;
}

TEST(LidarClock, ASynchronisedLidarKeepsItsOwnTimes) {
  using namespace std::chrono;
  LidarClock clock;
  for (const auto& p : packets_from(Clock::now(), microseconds(0), 2000)) {
    const auto t = clock.to_local(vlp16_packet_time(p.us_past_hour, p.received), p.received);
    ASSERT_LT(abs(duration_cast<microseconds>(t - p.sent)).count(), 1) << "the lidar's time, not the arrival";
  }
  EXPECT_TRUE(clock.synchronised());
  EXPECT_EQ(clock.correction(), Clock::duration(0));
}

TEST(LidarClock, AFreeRunningLidarIsMovedOntoOurClock) {
  using namespace std::chrono;
  // Without GPS a VLP-16 counts from power-on: 17 min 3.25 s behind here. Its stamps would
  // be minutes from every camera image; moved, they are within the fastest packet's
  // latency of when the packets left, also across the lidar's hour and after a restart.
  LidarClock clock;
  const auto start = floor<hours>(Clock::now()) + minutes(17) + seconds(1);  // the lidar's hour turns
  const auto behind = minutes(17) + milliseconds(3250);
  int k = 0;
  for (const auto& p : packets_from(start, behind, 3000)) {
    const auto t = clock.to_local(vlp16_packet_time(p.us_past_hour, p.received), p.received);
    if (++k > 10) ASSERT_LT(abs(duration_cast<microseconds>(t - p.sent)).count(), 300) << "packet " << k;
  }
  EXPECT_FALSE(clock.synchronised());
  EXPECT_NEAR(duration<double>(clock.correction()).count(), duration<double>(behind).count(), 0.001);
  // The lidar restarts: its clock is now 2 s behind ours; within two windows all is well.
  k = 0;
  for (const auto& p : packets_from(start + seconds(10), seconds(2), 3000)) {
    const auto t = clock.to_local(vlp16_packet_time(p.us_past_hour, p.received), p.received);
    if (p.sent > start + seconds(10) + 2 * LidarClock::kWindow) {
      ASSERT_LT(abs(duration_cast<microseconds>(t - p.sent)).count(), 300) << "packet " << k;
    }
    ++k;
  }
}

TEST(Vlp16, RotationsFromTheSyntheticSceneOverLoopbackUdp) {
  const auto scene = test::textured_room();
  const Pose T_world_lidar = make_pose(Vec3(0.3, -0.2, 0.85), 0.4, 0, 0);
  const auto packets = test::vlp16_packets(scene, T_world_lidar, 160);

  const int rx = socket(AF_INET, SOCK_DGRAM, 0), tx = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(rx, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(rx, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  socklen_t len = sizeof addr;
  ASSERT_EQ(getsockname(rx, reinterpret_cast<sockaddr*>(&addr), &len), 0);
  int buffer = 4 << 20;
  setsockopt(rx, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
  timeval timeout{2, 0};
  setsockopt(rx, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);

  Vlp16Assembler assembler(Vlp16Calibration{}, "lidar");
  std::vector<PointCloud> rotations;
  std::vector<uint8_t> buf(2048);
  for (const auto& p : packets) {
    ASSERT_EQ(sendto(tx, p.data(), p.size(), 0, reinterpret_cast<sockaddr*>(&addr), sizeof addr), ssize_t(p.size()));
    const ssize_t n = recv(rx, buf.data(), buf.size(), 0);
    ASSERT_EQ(n, ssize_t(kVlp16PacketSize));
    for (auto& r : assembler.add_packet(buf.data(), static_cast<size_t>(n), Clock::now(), "udp")) rotations.push_back(std::move(r));
  }
  close(rx);
  close(tx);

  // 160 packets of 12 firings 0.398 deg apart: the azimuth wraps twice, giving one whole
  // rotation and the part before the first wrap. 32 returns per firing.
  ASSERT_EQ(rotations.size(), 2u);
  const PointCloud& full = rotations[1];
  EXPECT_NEAR(static_cast<double>(full.size()), 32 * 360 / 0.39813, 64);
  EXPECT_NEAR(full.time.back(), 0.1, 0.001);
  EXPECT_TRUE(std::is_sorted(full.time.begin(), full.time.end()));
  // Every point lies on a wall, the floor or the ceiling of the 9 x 7 x 3 m room (ranges
  // come in 2 mm steps; azimuths in 0.01 deg).
  for (size_t i = 0; i < full.size(); ++i) {
    const Vec3 w = T_world_lidar * full.points[i].cast<double>();
    const double off = std::min({std::abs(std::abs(w.x()) - 4.5), std::abs(std::abs(w.y()) - 3.5), std::abs(w.z()),
                                 std::abs(w.z() - 3)});
    ASSERT_LT(off, 0.002) << i << ": " << w.transpose();
  }
}

TEST(Vlp16, MalformedPacketsNameTheProblem) {
  Vlp16Assembler assembler(Vlp16Calibration{}, "lidar");
  const auto good = test::vlp16_packets(test::textured_room(), Pose::Identity(), 1)[0];
  auto error = [&](std::vector<uint8_t> p) {
    try {
      assembler.add_packet(p.data(), p.size(), Clock::now(), "udp 127.0.0.1:2368");
    } catch (const CloudFormatError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error(std::vector<uint8_t>(good.begin(), good.begin() + 512)),
            "udp 127.0.0.1:2368: 512 bytes, a VLP-16 data packet has 1206");
  auto p = good;
  p[301] = 0xEF;
  EXPECT_EQ(error(p), "udp 127.0.0.1:2368: block 3 does not start with the flag 0xFFEE");
  p = good;
  test::put16(p, 402, 36000);
  EXPECT_EQ(error(p), "udp 127.0.0.1:2368: block 4 azimuth 36000 is not below 36000 (0.01 deg)");
  p = good;
  p[1204] = 0x40;
  EXPECT_EQ(error(p), "udp 127.0.0.1:2368: unknown return mode byte 0x40 (0x37 strongest, 0x38 last, 0x39 dual)");
  EXPECT_EQ(assembler.packets(), 0u);
}

}  // namespace
}  // namespace omniview
