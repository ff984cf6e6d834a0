// The clients a user actually runs, against the real daemon: the `omniview` CLI (views,
// ptz, snapshot, stream, status, record, then the recording replayed by a second daemon)
// and the Python example on Debian's python3-grpcio.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "daemon_process.h"

namespace omniview::testing {
namespace {

namespace fs = std::filesystem;

class Clients : public ::testing::Test {
 protected:
  Clients() : daemon_(dir_, example_config(20, "views:\n  - {name: front, type: perspective, width: 320, height: 160}\n")) {}

  // Runs `omniview ARGS --server <the daemon>`.
  ProcessResult cli(const std::string& args) const {
    return run_process(std::string(OMNIVIEW_CLI) + " " + args + " --server " + daemon_.address());
  }

  TempDir dir_;
  DaemonProcess daemon_;
};

size_t count_lines(const fs::path& file) {
  std::ifstream in(file);
  size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

TEST_F(Clients, CliCreatesPointsAndSnapshotsAView) {
  const std::string view_file = dir_.write("ptz.yaml", R"(name: ptz
type: perspective
width: 200
height: 100
frame: base_link
pose: {xyz: [0, 0, 1], ypr_deg: [0, 0, 0]}
hfov_deg: 90
)");
  auto r = cli("views create --file " + view_file);
  ASSERT_EQ(r.exit_code, 0) << r.output;

  r = cli("ptz ptz --pan 30 --tilt 10 --zoom 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = cli("ptz ptz --relative --pan 15");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("pan 45.00"), std::string::npos) << r.output;

  // What `views get` prints is the view YAML schema, pose included.
  r = cli("views get ptz");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ypr_deg:\n    - 45"), std::string::npos) << r.output;

  const std::string png = (dir_.path() / "ptz.png").string();
  r = cli("snapshot ptz -o " + png);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat image = cv::imread(png, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(image.empty()) << r.output;
  EXPECT_EQ(image.cols, 200);
  EXPECT_EQ(image.rows, 100);
  EXPECT_GT(cv::mean(image)[0], 5);  // the cameras see the room, not black

  r = cli("views delete ptz");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = cli("snapshot ptz -o " + png);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("no view named 'ptz'"), std::string::npos) << r.output;
}

TEST_F(Clients, CliStreamsFramesWithAnIndexAndShowsStatus) {
  const fs::path folder = dir_.path() / "frames";
  auto r = cli("stream front --frames 5 -o " + folder.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_lines(folder / "frames.csv"), 6u);  // header + 5 frames
  const cv::Mat first = cv::imread((folder / "frame_000001.jpg").string());
  EXPECT_EQ(first.cols, 320);
  EXPECT_EQ(first.rows, 160);

  r = cli("status");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("examples"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("front"), std::string::npos) << r.output;
}

TEST_F(Clients, ARecordingReplaysInAnotherDaemon) {
  const fs::path recording = dir_.path() / "recording";
  auto r = cli("record -o " + recording.string() + " --frames 6");
  ASSERT_EQ(r.exit_code, 0) << r.output;

  const std::string config = "listen: 127.0.0.1:0\nsources:\n  - {name: lab, type: replay, recording: " +
                             recording.string() +
                             ", rate_hz: 15}\nviews:\n  - {name: front, type: perspective, width: 160, height: 80}\n";
  TempDir replay_dir;
  DaemonProcess replay(replay_dir, config);
  auto stub = make_stub(replay.address());
  v1::StreamFramesRequest req;
  req.set_view("front");
  req.set_encoding(v1::RAW);
  auto ctx = make_context();
  auto reader = stub->StreamFrames(ctx.get(), req);
  v1::Frame f;
  uint64_t last_sequence = 0;
  for (int i = 0; i < 10; ++i) {  // more than the recording holds: it loops
    ASSERT_TRUE(reader->Read(&f)) << replay.log();
    EXPECT_GT(f.sequence(), last_sequence);
    last_sequence = f.sequence();
  }
  EXPECT_EQ(f.width(), 160);
  EXPECT_EQ(f.height(), 80);
  ctx->TryCancel();
  reader->Finish();
}

TEST_F(Clients, ThePythonExampleSavesFrames) {
  const fs::path folder = dir_.path() / "py_frames";
  // Debian's interpreter: the example uses Debian's python3-grpcio, not a pip install.
  // XDG_CACHE_HOME keeps the generated modules inside the test's scratch folder.
  const std::string command = "XDG_CACHE_HOME=" + (dir_.path() / "cache").string() + " " + OMNIVIEW_DEBIAN_PYTHON +
                              " " + OMNIVIEW_SOURCE_DIR + "/examples/python/save_frames.py front --frames 3 -o " +
                              folder.string() + " --server " + daemon_.address();
  const auto r = run_process(command);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (int i = 1; i <= 3; ++i) {
    const cv::Mat frame = cv::imread((folder / ("frame_00000" + std::to_string(i) + ".jpg")).string());
    EXPECT_EQ(frame.cols, 320) << r.output;
    EXPECT_EQ(frame.rows, 160);
  }
  EXPECT_NE(r.output.find("saved 3 frames"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace omniview::testing
