// The black box's ring on disk (server/blackbox): within its byte budget at every write,
// oldest seconds first; read back after a restart, a crash mid-write included; joined into
// one ordinary recording by a snapshot.
#include "server/blackbox/black_box_ring.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "server/blackbox/snapshot_merge.h"
#include "server/recording/recording.h"

namespace omniview {
namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;
using SystemClock = std::chrono::system_clock;

std::shared_ptr<Rig> small_rig() {
  auto rig = std::make_shared<Rig>();
  for (const char* name : {"left", "right"}) {
    Camera cam;
    cam.name = name;
    cam.width = 32;
    cam.height = 24;
    cam.model = make_camera_model({"pinhole", "none", {20, 20, 15.5, 11.5}, {}}, name);
    cam.T_parent_cam = make_pose(Vec3(0, name[0] == 'l' ? 0.1 : -0.1, 1), 0, 0, 0);
    rig->add_camera(cam);
  }
  return rig;
}

// A frame set as a robot sends it: each camera's JPEG bytes as received (here `bytes` of
// noise: the ring stores them as they are and never decodes them).
FrameSet robot_frames(const std::shared_ptr<Rig>& rig, uint64_t sequence, SystemClock::time_point t,
                      size_t bytes = 50000) {
  FrameSet frames;
  frames.sequence = sequence;
  frames.capture_time = t;
  frames.rig = rig;
  frames.images.resize(rig->cameras().size());
  for (size_t i = 0; i < rig->cameras().size(); ++i) {
    auto data = std::make_shared<std::vector<uint8_t>>(bytes);
    cv::Mat view(1, static_cast<int>(bytes), CV_8UC1, data->data());
    cv::RNG(static_cast<uint64_t>(sequence * 10 + i)).fill(view, cv::RNG::UNIFORM, 0, 256);
    frames.encoded.push_back({"jpeg", data});
  }
  return frames;
}

// What `du` says the folder takes, in bytes: the ring's budget is about real disk use.
uint64_t du_bytes(const fs::path& folder) {
  const std::string command = "du -s -B1 '" + folder.string() + "' | cut -f1";
  FILE* pipe = popen(command.c_str(), "r");
  uint64_t bytes = 0;
  if (pipe != nullptr) {
    if (std::fscanf(pipe, "%lu", &bytes) != 1) bytes = 0;
    pclose(pipe);
  }
  return bytes;
}

class BlackBoxRingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("black_box_ring_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  std::shared_ptr<Rig> rig_ = small_rig();
  SystemClock::time_point t0_ = SystemClock::now() - 60s;
  std::vector<std::string> log_;
  std::function<void(const std::string&)> logger_ = [this](const std::string& line) { log_.push_back(line); };
};

TEST_F(BlackBoxRingTest, StaysWithinItsBudgetAtEveryWriteDroppingTheOldestFirst) {
  BlackBoxRingOptions options;
  options.span = 10min;            // the budget, not the span, decides here
  options.max_bytes = 8u << 20;    // ~80 frame sets of 2 x 50 kB
  BlackBoxRing ring(dir_ / "ring", "robot", options, logger_);
  for (int i = 0; i < 400; ++i) {  // 40 s at 10 Hz: ~40 MB through an 8 MB ring
    ASSERT_TRUE(ring.write(robot_frames(rig_, i, t0_ + i * 100ms)));
    ASSERT_LE(ring.bytes(), options.max_bytes) << "frame set " << i;
    if (i % 50 == 0) {
      ASSERT_LE(du_bytes(ring.folder()), options.max_bytes) << "frame set " << i;
    }
  }
  ring.seal();
  EXPECT_LE(du_bytes(ring.folder()), options.max_bytes);
  EXPECT_GT(ring.bytes(), options.max_bytes * 3 / 4) << "the ring should use most of its budget";
  // The newest seconds are there, the oldest went.
  EXPECT_EQ(ring.segments().back().last, t0_ + 399 * 100ms);
  EXPECT_GT(ring.segments().front().first, t0_ + 20s);
  EXPECT_GT(ring.span().count(), 5.0);
  EXPECT_GE(ring.segments().size(), 7u);
  EXPECT_TRUE(log_.empty()) << log_.front();
}

TEST_F(BlackBoxRingTest, KeepsItsSpanAndNoMore) {
  BlackBoxRingOptions options;
  options.span = 20s;  // segments of 2 s
  options.max_bytes = 1u << 30;
  BlackBoxRing ring(dir_ / "ring", "robot", options, logger_);
  for (int i = 0; i < 600; ++i) ring.write(robot_frames(rig_, i, t0_ + i * 100ms, 2000));
  EXPECT_GE(ring.span().count(), 20.0);
  EXPECT_LE(ring.span().count(), 20.0 + 2.0 + 0.1) << "at most a segment more than the span";
  EXPECT_EQ(ring.segment_length(), 2000ms);
}

TEST_F(BlackBoxRingTest, OutlivesARestartEvenAKillMidWrite) {
  BlackBoxRingOptions options;
  options.max_bytes = 64u << 20;
  size_t written = 0;
  {
    BlackBoxRing ring(dir_ / "ring", "robot", options, logger_);
    for (int i = 0; i < 50; ++i) ring.write(robot_frames(rig_, i, t0_ + i * 100ms, 3000));
    written = ring.frame_sets();
    // A kill mid-write: the open segment's index ends in half a line (the ring's own
    // destructor would close it properly; this is what a SIGKILL leaves).
    std::ofstream(ring.segments().back().folder / "frames.csv", std::ios::app) << "50,17000";
  }
  // A segment of another version, and one cut short before its first frame.
  fs::create_directories(dir_ / "ring" / "00000000000000000001");
  std::ofstream(dir_ / "ring" / "00000000000000000001" / "recording.yaml")
      << "format: omniview-recording\nversion: 99\ncameras: [left, right]\n";
  std::ofstream(dir_ / "ring" / "00000000000000000001" / "frames.csv") << "sequence,capture_time_ns,rig,left,right\n";
  fs::create_directories(dir_ / "ring" / "99999999999999999999" / "images");

  BlackBoxRing again(dir_ / "ring", "robot", options, logger_);
  EXPECT_EQ(again.frame_sets(), written);
  EXPECT_EQ(again.segments().back().last, t0_ + 49 * 100ms);
  ASSERT_EQ(log_.size(), 2u);
  EXPECT_NE(log_[0].find("00000000000000000001"), std::string::npos) << log_[0];
  EXPECT_NE(log_[0].find("version"), std::string::npos) << log_[0];
  EXPECT_FALSE(fs::exists(dir_ / "ring" / "99999999999999999999"));
  // And it goes on where it was.
  again.write(robot_frames(rig_, 50, t0_ + 5000ms, 3000));
  EXPECT_EQ(again.frame_sets(), written + 1);
}

// The minutes before a crash or a power cut stay however long the daemon was down, until
// newer frame sets push them out of the span.
TEST_F(BlackBoxRingTest, WhatIsOlderThanTheSpanStaysUntilNewFramesComeAfterARestart) {
  BlackBoxRingOptions options;
  options.span = 30s;
  {
    BlackBoxRing ring(dir_ / "ring", "robot", options, logger_);
    const auto an_hour_ago = SystemClock::now() - 1h;
    for (int i = 0; i < 10; ++i) ring.write(robot_frames(rig_, i, an_hour_ago + i * 100ms, 1000));
  }
  BlackBoxRing again(dir_ / "ring", "robot", options, logger_);
  EXPECT_EQ(again.frame_sets(), 10u);
  again.write(robot_frames(rig_, 10, SystemClock::now(), 1000));
  EXPECT_EQ(again.frame_sets(), 1u) << "the hour-old segment is outside the span of the new frame set";
}

// A write that fails (a disk with less room than max_bytes filled up, a folder removed
// under it): the segment is closed, the oldest one goes to make room, and the next write
// starts a fresh segment.
TEST_F(BlackBoxRingTest, AWriteErrorDropsTheOldestAndTheNextWriteStartsAFreshSegment) {
  BlackBoxRingOptions options;
  options.span = 20s;  // segments of 2 s
  BlackBoxRing ring(dir_ / "ring", "robot", options, logger_);
  for (int i = 0; i < 50; ++i) ring.write(robot_frames(rig_, i, t0_ + i * 100ms, 1000));
  ASSERT_EQ(ring.segments().size(), 3u);
  const fs::path oldest = ring.segments().front().folder;
  fs::remove_all(ring.segments().back().folder);
  try {
    ring.write(robot_frames(rig_, 50, t0_ + 5000ms, 1000));
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos) << "the system's reason: " << e.what();
  }
  EXPECT_FALSE(fs::exists(oldest));
  EXPECT_EQ(ring.segments().size(), 1u) << "the oldest dropped, the vanished one forgotten";
  EXPECT_TRUE(ring.write(robot_frames(rig_, 51, t0_ + 5100ms, 1000)));
  EXPECT_EQ(ring.stage(dir_ / "staging").size(), 1u) << "every segment listed can be staged";
  EXPECT_NO_THROW(Recording::open(ring.segments().back().folder.string()));
}

TEST_F(BlackBoxRingTest, AFolderThatCannotBeMadeIsNamedInTheError) {
  fs::create_directories(dir_);
  std::ofstream(dir_ / "a-file") << "x";
  try {
    BlackBoxRing ring(dir_ / "a-file" / "ring", "robot", {}, logger_);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("a-file/ring"), std::string::npos) << e.what();
  }
}

TEST_F(BlackBoxRingTest, AFrameSetLargerThanASegmentIsRefusedNotKeptHalf) {
  BlackBoxRingOptions options;
  options.max_bytes = 4u << 20;  // segments of 512 kB
  BlackBoxRing ring(dir_ / "ring", "robot", options, logger_);
  EXPECT_FALSE(ring.write(robot_frames(rig_, 0, t0_, 400000)));
  EXPECT_EQ(ring.frame_sets(), 0u);
  EXPECT_TRUE(ring.write(robot_frames(rig_, 1, t0_, 100000)));
}

// A source that decodes smaller for its views (a JPEG's DCT scaling: the Insta360 Air) still
// has the whole image's bytes as received: those are kept, the small pixels are not asked about.
TEST_F(BlackBoxRingTest, KeepsTheBytesOfImagesTheSourceDecodedSmaller) {
  BlackBoxRing ring(dir_ / "ring", "robot", {}, logger_);
  FrameSet frames = robot_frames(rig_, 0, t0_, 1000);
  for (auto& image : frames.images) image = cv::Mat(12, 16, CV_8UC1, cv::Scalar(0));  // half the calibration's size
  EXPECT_TRUE(ring.write(frames));
  EXPECT_EQ(ring.frame_sets(), 1u);
}

TEST_F(BlackBoxRingTest, ASnapshotIsOneOrdinaryRecordingOfEverySegment) {
  BlackBoxRingOptions options;
  options.span = 20s;
  BlackBoxRing ring(dir_ / "ring", "robot", options, logger_);
  auto cloud = std::make_shared<PointCloud>();
  cloud->frame = "base_link";
  cloud->stamp = t0_;
  cloud->points = {{1, 2, 3}, {4, 5, 6}};
  for (int i = 0; i < 70; ++i) {  // 7 s: four segments
    FrameSet frames = robot_frames(rig_, 100 + i, t0_ + i * 100ms, 1500);
    frames.joints = std::make_shared<const std::map<std::string, double>>(std::map<std::string, double>{{"knee", 0.01 * i}});
    if (i % 10 == 0) frames.cloud = cloud;
    ring.write(frames);
  }
  ring.seal();
  ASSERT_GE(ring.segments().size(), 3u);
  const auto staged = ring.stage(dir_ / "staging");
  ASSERT_EQ(staged.size(), ring.segments().size());
  const SnapshotSummary saved = merge_segments(staged, dir_ / "snapshot", "robot");
  EXPECT_EQ(saved.frame_sets, 70u);
  EXPECT_NEAR(saved.span.count(), 6.9, 1e-6);
  EXPECT_EQ(saved.note, "");
  const Recording r = Recording::open((dir_ / "snapshot").string());
  ASSERT_EQ(r.frames.size(), 70u);
  EXPECT_EQ(r.source_name, "robot");
  EXPECT_EQ(r.frames[69].sequence, 169u);
  EXPECT_EQ(r.frames[69].capture_time, t0_ + 6900ms);
  ASSERT_TRUE(r.frames[69].joints);
  EXPECT_DOUBLE_EQ(r.frames[69].joints->at("knee"), 0.69);
  EXPECT_EQ(r.load_cloud(r.frames[60])->points.size(), 2u);
  EXPECT_EQ(r.load_cloud(r.frames[61]), nullptr);
  // The images as received, byte for byte.
  const FrameSet original = robot_frames(rig_, 133, t0_ + 3300ms, 1500);
  std::ifstream in(fs::path(r.folder) / r.frames[33].image_files[1], std::ios::binary);
  const std::vector<uint8_t> stored((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(stored, *original.encoded[1].bytes);
  // Staged by hard links: the ring may drop its segments meanwhile.
  fs::remove_all(dir_ / "ring");
  EXPECT_TRUE(fs::exists(staged.front() / "frames.csv"));
}

}  // namespace
}  // namespace omniview
