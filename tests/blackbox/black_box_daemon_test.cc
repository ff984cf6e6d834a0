// The black box in omniviewd (`blackbox:`), from outside: a robot (the real spot-mock) sent
// away leaves a snapshot of the minutes before; a daemon killed mid-write keeps all but its
// last second and serves its ring again after the restart; `omniview blackbox save` and
// `omniview status` as an operator uses them; snapshots replay and export like any recording.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "server/blackbox/black_box_ring.h"
#include "server/recording/recording.h"
#include "tests/server/daemon_process.h"
#include "tests/spot_mock/spot_mock_process.h"

namespace omniview::testing {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using SystemClock = std::chrono::system_clock;

const std::string kView = "views:\n  - {name: front, type: perspective, width: 160, height: 120, frame: base_link}\n";
const std::string kSpotView = "views:\n  - {name: front, type: perspective, width: 160, height: 120, frame: body}\n";

// Watches a view (JPEG frames) on its own thread for as long as it lives: sources deliver,
// and the black box keeps, only while someone watches.
class Watcher {
 public:
  Watcher(v1::Omniview::Stub& stub, const std::string& view) {
    context_ = make_context("", 600s);
    v1::StreamFramesRequest r;
    r.set_view(view);
    reader_ = stub.StreamFrames(context_.get(), r);
    thread_ = std::thread([this] {
      v1::Frame f;
      while (reader_->Read(&f)) ++count_;
    });
  }
  ~Watcher() {
    context_->TryCancel();
    thread_.join();
  }
  size_t count() const { return count_; }

 private:
  std::unique_ptr<grpc::ClientContext> context_;
  std::unique_ptr<grpc::ClientReader<v1::Frame>> reader_;
  std::thread thread_;
  std::atomic<size_t> count_{0};
};

v1::Status status_of(v1::Omniview::Stub& stub) {
  v1::Status s;
  stub.GetStatus(make_context().get(), v1::GetStatusRequest(), &s);
  return s;
}

// The newest capture time in any readable segment of a ring folder.
SystemClock::time_point newest_in_ring(const fs::path& ring) {
  SystemClock::time_point newest{};
  for (const auto& entry : fs::directory_iterator(ring)) {
    try {
      const Recording r = Recording::open(entry.path().string());
      newest = std::max(newest, r.frames.back().capture_time);
    } catch (const std::exception&) {
    }
  }
  return newest;
}

double seconds_between(SystemClock::time_point a, SystemClock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

TEST(BlackBoxDaemon, ARobotSentAwayLeavesASnapshotOfTheMinutesBeforeThatReplays) {
  TempDir dir;
  auto mock = std::make_unique<SpotMockProcess>(dir.path(), std::vector<std::string>{"--scene", "test"});
  const fs::path box = dir.path() / "box";
  std::ostringstream config;
  config << "listen: 127.0.0.1:0\nsources:\n  - name: spot\n    type: spot\n"
         << "    robot: 127.0.0.1:" << mock->port() << "\n    ca_file: " << mock->certs_dir() << "/ca.pem\n"
         << "    credentials_file: " << mock->credentials_file() << "\n    rate_hz: 10\n"
         << kSpotView << "blackbox: {minutes: 0.25, max_bytes: 12M, folder: " << box.string() << "}\n";
  DaemonProcess daemon(dir, config.str());
  auto stub = make_stub(daemon.address());
  {
    Watcher watching(*stub, "front");
    ASSERT_TRUE(eventually_within(
        [&] {
          const auto s = status_of(*stub);
          return s.blackbox_size() == 1 && s.blackbox(0).frame_sets() >= 30;
        },
        30s))
        << status_of(*stub).DebugString() << daemon.log();
    const auto sent_away = SystemClock::now();
    mock->stop(9);  // out of Wi-Fi reach: no answer at all
    // The snapshot made for this drop: its newest frame set from just before it.
    fs::path snapshot;
    ASSERT_TRUE(eventually_within(
        [&] {
          const std::string last = status_of(*stub).blackbox(0).last_snapshot();
          if (last.find("spot-lost-") == std::string::npos) return false;
          try {
            const Recording r = Recording::open(last);
            if (seconds_between(r.frames.back().capture_time, sent_away) > time_scaled(2s).count() / 1000.0) return false;
          } catch (const std::exception&) {
            return false;
          }
          snapshot = last;
          return true;
        },
        40s))
        << status_of(*stub).DebugString() << daemon.log();
    const Recording saved = Recording::open(snapshot.string());
    EXPECT_GE(saved.frames.size(), 30u);
    EXPECT_EQ(saved.source_name, "spot");
    EXPECT_EQ(saved.camera_names.size(), 5u);
    EXPECT_GE(seconds_between(saved.frames.front().capture_time, saved.frames.back().capture_time), 2.0);
    EXPECT_NE(daemon.log().find("black box: 'spot' lost its connection: saved the"), std::string::npos) << daemon.log();
    // The ring never over its budget (du's blocks, not the files' sizes).
    EXPECT_LE(folder_disk_bytes(box / "ring" / "spot"), 12u << 20);
    EXPECT_EQ(status_of(*stub).blackbox(0).max_bytes(), 12u << 20);

    // The snapshot is an ordinary recording: a replay daemon serves the same view from it.
    TempDir replay_dir;
    DaemonProcess replay(replay_dir, "listen: 127.0.0.1:0\nsources:\n  - {name: replay, type: replay, recording: " +
                                         snapshot.string() + "}\n" + kSpotView);
    auto replay_stub = make_stub(replay.address());
    v1::SnapshotRequest request;
    request.set_view("front");
    v1::Frame frame;
    const grpc::Status got = replay_stub->GetSnapshot(make_context("", time_scaled(20s)).get(), request, &frame);
    ASSERT_TRUE(got.ok()) << got.error_message() << replay.log();
    EXPECT_GT(frame.data().size(), 0u);
  }
}

TEST(BlackBoxDaemon, AKillMidWriteLosesAtMostTheLastSecondAndTheRingServesOnAfterARestart) {
  TempDir dir;
  const fs::path box = dir.path() / "box";
  const std::string config =
      example_config(10, kView + "blackbox: {minutes: 1, max_bytes: 64M, folder: " + box.string() + "}\n");
  SystemClock::time_point killed;
  size_t kept = 0;
  {
    DaemonProcess daemon(dir, config);
    auto stub = make_stub(daemon.address());
    Watcher watching(*stub, "front");
    ASSERT_TRUE(eventually_within([&] { return status_of(*stub).blackbox(0).frame_sets() >= 20; }, 30s))
        << status_of(*stub).DebugString() << daemon.log();
    kept = status_of(*stub).blackbox(0).frame_sets();
    killed = SystemClock::now();
    EXPECT_EQ(daemon.stop(9), 128 + 9);
  }
  const double lost_s = seconds_between(newest_in_ring(box / "ring" / "examples"), killed);
  EXPECT_LT(lost_s, time_scaled(1s).count() / 1000.0) << "the ring's newest frame set is " << lost_s << " s before the kill";

  // Started again on the same folder: what was kept is there, status says so at once.
  DaemonProcess again(dir, config);
  auto stub = make_stub(again.address());
  const v1::Status s = status_of(*stub);
  ASSERT_EQ(s.blackbox_size(), 1);
  EXPECT_GE(s.blackbox(0).frame_sets(), kept);
  EXPECT_GT(s.blackbox(0).span_s(), 1.0);
  EXPECT_NE(again.log().find("black box: 'examples': kept"), std::string::npos) << again.log();
  // Killed, the last run left its ring open: saved at once, before new frame sets push it out.
  EXPECT_NE(again.log().find("stopped without closing its black box"), std::string::npos) << again.log();
  ASSERT_NE(s.blackbox(0).last_snapshot().find("examples-crash-"), std::string::npos) << s.DebugString();
  EXPECT_GE(Recording::open(s.blackbox(0).last_snapshot()).frames.size(), kept);
  const std::string status_text = run_process(std::string(OMNIVIEW_CLI) + " status --server " + again.address()).output;
  EXPECT_NE(status_text.find("black box"), std::string::npos) << status_text;

  // Saved by hand (`omniview blackbox save`), and exported to MCAP like any recording.
  const auto save = [&](const std::string& name) {
    return run_process(std::string(OMNIVIEW_CLI) + " blackbox save " + name + " --server " + again.address() + " 2>&1");
  };
  const auto saved = save("before-the-kill");
  ASSERT_EQ(saved.exit_code, 0) << saved.output;
  EXPECT_NE(saved.output.find("saved source 'examples'"), std::string::npos) << saved.output;
  const fs::path snapshot = box / "snapshots" / "before-the-kill";
  const Recording r = Recording::open(snapshot.string());
  EXPECT_GE(r.frames.size(), kept);
  const auto twice = save("before-the-kill");
  EXPECT_NE(twice.exit_code, 0);
  EXPECT_NE(twice.output.find("exists already"), std::string::npos) << twice.output;
  const auto bad = save("../escape");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("snapshot name"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(box / "escape"));
  const auto exported = run_process(std::string(OMNIVIEW_CLI) + " export " + snapshot.string() + " -o " +
                                    (dir.path() / "snapshot.mcap").string() + " --no-clouds 2>&1");
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_GT(fs::file_size(dir.path() / "snapshot.mcap"), 1000u);
}

TEST(BlackBoxDaemon, ViewersMayNotSaveAndADaemonWithoutOneSaysHowToHaveOne) {
  TempDir dir;
  const std::string viewer = "viewer-token-5b1e0c9d3a7f4e22";
  DaemonProcess daemon(dir, example_config(10, kView + "tokens:\n  - {role: viewer, token: " + viewer + "}\n"));
  auto stub = make_stub(daemon.address());
  v1::SaveBlackBoxRequest request;
  request.set_name("x");
  v1::SaveBlackBoxResponse response;
  EXPECT_EQ(stub->SaveBlackBox(make_context(viewer).get(), request, &response).error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
  TempDir plain_dir;
  DaemonProcess plain(plain_dir, example_config(10, kView));
  auto plain_stub = make_stub(plain.address());
  const grpc::Status none = plain_stub->SaveBlackBox(make_context().get(), request, &response);
  EXPECT_EQ(none.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(none.error_message().find("blackbox:"), std::string::npos) << none.error_message();
}

TEST(BlackBoxDaemon, AnUnwritableFolderIsAConfigErrorNamingIt) {
  TempDir dir;
  std::ofstream(dir.path() / "a-file") << "x";
  const auto config = dir.path() / "omniviewd.yaml";
  std::ofstream(config) << example_config(10, kView + "blackbox: {folder: " + (dir.path() / "a-file").string() + "/box}\n");
  const auto r = run_process(std::string(OMNIVIEWD) + " --config " + config.string() + " --check 2>&1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("blackbox.folder"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("a-file/box"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace omniview::testing
