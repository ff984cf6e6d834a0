// The clients a user actually runs, against the real daemon: the `omniview` CLI (views,
// ptz, snapshot, stream, status, record, then the recording replayed by a second daemon)
// and the Python example on Debian's python3-grpcio.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/core.hpp>

#include "core/io/image_codec.h"
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

std::string file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The sequence numbers of a recording's frames.csv, in order.
std::vector<uint64_t> recorded_sequences(const fs::path& recording) {
  std::ifstream in(recording / "frames.csv");
  std::vector<uint64_t> sequences;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) sequences.push_back(std::stoull(line.substr(0, line.find(','))));
  return sequences;
}

// `omniview record -o FOLDER ...` made a deliberately slow client: once the recording has
// its first frame sets on disk (a loaded machine may take a while to get there), the CLI is
// stopped (SIGSTOP) for `stall`, as a disk that blocks would stop it.
ProcessResult record_with_stall(const std::string& server, const fs::path& folder, const std::string& args,
                                double stall) {
  const std::string index = (folder / "frames.csv").string();
  std::ostringstream command;
  command << "{ " << OMNIVIEW_CLI << " record -o " << folder.string() << " " << args << " --server " << server
          << " & p=$!; for i in $(seq 400); do [ \"$(wc -l < " << index
          << " 2>/dev/null || echo 0)\" -ge 4 ] && break; sleep 0.05; done; kill -STOP $p; sleep " << stall
          << "; kill -CONT $p; wait $p; }";
  return run_process(command.str());
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
  const cv::Mat image = read_image(png);
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
  const cv::Mat first = read_image(folder / "frame_000001.jpg", ImageColour::kBgr);
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
  EXPECT_NE(r.output.find("recorded 6 frame sets, skipped 0,"), std::string::npos) << r.output;
  // The source's JPEG files, byte for byte: nothing decoded and re-encoded on the way.
  EXPECT_EQ(file_bytes(recording / "images/0_0.jpg"), file_bytes(example_dir() + "/front.jpg"));
  EXPECT_EQ(file_bytes(recording / "images/5_1.jpg"), file_bytes(example_dir() + "/back.jpg"));

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

  // A recording of the replay keeps the bytes too.
  const fs::path again = dir_.path() / "again";
  r = run_process(std::string(OMNIVIEW_CLI) + " record -o " + again.string() + " --frames 2 --server " +
                  replay.address());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(file_bytes(again / "images/1_0.jpg"), file_bytes(example_dir() + "/front.jpg"));
}

TEST_F(Clients, ARecordingSlowForAMomentLosesNothing) {
  // 0.6 s stopped at 20 Hz: 12 frame sets, within the daemon's default queue of 32.
  const fs::path recording = dir_.path() / "recording";
  const auto r = record_with_stall(daemon_.address(), recording, "--frames 30", 0.6);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("recorded 30 frame sets, skipped 0,"), std::string::npos) << r.output;
  const auto sequences = recorded_sequences(recording);
  ASSERT_EQ(sequences.size(), 30u);
  for (size_t i = 1; i < sequences.size(); ++i) EXPECT_EQ(sequences[i], sequences[i - 1] + 1) << "none lost";
}

TEST(Recording, AClientFarBehindSkipsAndSaysHowMany) {
  // A queue of 4 at 30 Hz, and the client stopped for 5 s: up to 150 frame sets, far more
  // than the queue and what the connection buffers (a few MB of ~150 KB frame sets), even
  // when a loaded machine delivers at half the rate.
  TempDir dir;
  DaemonProcess daemon(dir, example_config(30, "limits: {record_queue_frame_sets: 4}\n"));
  const fs::path recording = dir.path() / "recording";
  const auto r = record_with_stall(daemon.address(), recording, "--frames 40", 5.0);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto sequences = recorded_sequences(recording);
  ASSERT_EQ(sequences.size(), 40u);
  const size_t at = r.output.find("recorded 40 frame sets, skipped ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const uint64_t skipped = std::stoull(r.output.substr(at + 32));
  EXPECT_GT(skipped, 0u) << r.output;
  // Exactly what is missing: recorded + skipped spans first to last sequence.
  EXPECT_EQ(sequences.size() + skipped, sequences.back() - sequences.front() + 1) << r.output;
  EXPECT_NE(r.output.find("limits.record_queue_frame_sets"), std::string::npos) << r.output;
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
    const cv::Mat frame = read_image(folder / ("frame_00000" + std::to_string(i) + ".jpg"), ImageColour::kBgr);
    EXPECT_EQ(frame.cols, 320) << r.output;
    EXPECT_EQ(frame.rows, 160);
  }
  EXPECT_NE(r.output.find("saved 3 frames"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace omniview::testing
