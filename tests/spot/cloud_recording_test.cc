// Recordings keep clouds: spot-mock's lidar recorded with `omniview record` (which asks the
// robot for clouds by itself, with nobody watching one), then replayed by a second
// omniviewd, whose StreamClouds gives the same points.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "server/recording/recording.h"
#include "tests/server/daemon_process.h"
#include "tests/spot_mock/spot_mock_process.h"

namespace omniview::testing {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

std::chrono::milliseconds scaled(std::chrono::milliseconds t) {
  return std::chrono::milliseconds(static_cast<int64_t>(t.count() * test_time_scale()));
}

// x, y, z of each point, by the message's own field list.
std::vector<Eigen::Vector3f> points_of(const v1::PointCloud& c) {
  std::map<std::string, uint32_t> offset;
  for (const auto& f : c.fields()) offset[f.name()] = f.offset();
  std::vector<Eigen::Vector3f> out(c.point_count());
  for (size_t i = 0; i < out.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      std::memcpy(&out[i][k], c.data().data() + i * c.point_stride() + offset[std::string(1, "xyz"[k])], 4);
    }
  }
  return out;
}

// The first cloud of `source` streamed in `frame` (its own frame: no transform, no rounding).
v1::PointCloud first_cloud(v1::Omniview::Stub& stub, const std::string& source, const std::string& frame) {
  v1::StreamCloudsRequest request;
  request.set_source(source);
  request.mutable_options()->set_frame(frame);
  auto ctx = make_context("", scaled(20s));
  auto reader = stub.StreamClouds(ctx.get(), request);
  v1::PointCloud cloud;
  EXPECT_TRUE(reader->Read(&cloud)) << reader->Finish().error_message();
  ctx->TryCancel();
  return cloud;
}

TEST(CloudRecording, RecordedCloudsComeBackFromAReplay) {
  TempDir dir;
  SpotMockProcess mock(dir.path(), {"--scene", "test", "--rgb", "--supersample", "1"});
  std::ostringstream config;
  config << "listen: 127.0.0.1:0\nsources:\n  - name: spot\n    type: spot\n"
         << "    robot: 127.0.0.1:" << mock.port() << "\n    ca_file: " << mock.certs_dir() << "/ca.pem\n"
         << "    credentials_file: " << mock.credentials_file() << "\n    pixel_format: rgb\n    rate_hz: 10\n";
  DaemonProcess live(dir, config.str());
  auto stub = make_stub(live.address());

  const fs::path folder = dir.path() / "recording";
  const auto recorded = run_process(std::string(OMNIVIEW_CLI) + " record -o " + folder.string() +
                                    " --frames 6 --source spot --server " + live.address());
  ASSERT_EQ(recorded.exit_code, 0) << recorded.output;

  const Recording recording = Recording::open(folder.string());
  std::vector<std::shared_ptr<PointCloud>> clouds;
  for (const auto& frame : recording.frames) {
    if (auto c = recording.load_cloud(frame)) clouds.push_back(c);
  }
  ASSERT_FALSE(clouds.empty()) << "no frame set of the recording kept a cloud";
  EXPECT_GT(clouds.front()->size(), 1000u);

  std::ostringstream replay;
  replay << "listen: 127.0.0.1:0\nsources:\n  - name: replay\n    type: replay\n    recording: " << folder.string()
         << "\n    rate_hz: 10\n";
  TempDir replay_dir;
  DaemonProcess player(replay_dir, replay.str());
  auto replay_stub = make_stub(player.address());
  const v1::PointCloud back = first_cloud(*replay_stub, "replay", clouds.front()->frame);
  const auto points = points_of(back);
  ASSERT_FALSE(points.empty());
  // The same points as one of the recorded clouds (spot-mock's scene stands still, so they
  // may all be alike: any one will do).
  bool same = false;
  for (const auto& c : clouds) {
    if (c->size() != points.size()) continue;
    bool all = true;
    for (size_t i = 0; i < points.size() && all; ++i) all = (c->points[i] - points[i]).norm() < 1e-5f;
    same = same || all;
  }
  EXPECT_TRUE(same) << points.size() << " points back, recorded clouds have " << clouds.front()->size();
  EXPECT_GT(back.counts().coloured(), 0u) << "the replayed images colour the replayed cloud";
}

}  // namespace
}  // namespace omniview::testing
