// The `replay` source: order, timing, looping, bad images, config errors.
#include <fstream>

#include <opencv2/core.hpp>

#include "server/recording/recording.h"
#include "server/sources/replay_source.h"
#include "tests/sources/source_test_support.h"

namespace omniview {
namespace {
using namespace omniview::testing;
using namespace std::chrono_literals;

std::shared_ptr<Rig> small_rig(double x) {
  auto rig = std::make_shared<Rig>();
  Camera cam;
  cam.name = "cam";
  cam.width = 16;
  cam.height = 12;
  cam.model = make_camera_model({"pinhole", "none", {10, 10, 7.5, 5.5}, {}}, "cam");
  cam.T_parent_cam = make_pose(Vec3(x, 0, 1), 0, 0, 0);
  rig->add_camera(cam);
  return rig;
}

// Five frames `interval` apart; frame i is filled with 10 * (i + 1) and the last two use a
// second rig.
void write_recording(const std::string& folder, std::chrono::milliseconds interval) {
  RecordingWriter writer(folder, "robot");
  const auto first = small_rig(0), second = small_rig(1);
  const auto t0 = std::chrono::system_clock::time_point(std::chrono::seconds(1600000000));
  for (int i = 0; i < 5; ++i) {
    FrameSet frames;
    frames.sequence = 100 + i;
    frames.capture_time = t0 + interval * i;
    frames.rig = i < 3 ? first : second;
    frames.images = {cv::Mat(12, 16, CV_8UC1, cv::Scalar(10 * (i + 1)))};
    writer.write(frames);
  }
}

int value_of(const FrameSet& frames) { return frames.images.at(0).at<uint8_t>(0, 0); }

double seconds_between(const FrameSet& a, const FrameSet& b) {
  return std::chrono::duration<double>(b.arrival - a.arrival).count();
}

TEST(ReplaySource, PlaysInOrderWithRecordedTimingAndLoops) {
  TempFolder dir;
  write_recording(dir / "rec", 40ms);
  TestConfig config("name: r\ntype: replay\nrecording: rec\nspeed: 2\n", dir.str());
  ReplaySource source(config.config);
  EXPECT_EQ(source.type(), "replay");
  Collector collector;
  source.start(collector.callback());
  const auto frames = collector.wait_for(12, 2s);
  source.stop();
  ASSERT_GE(frames.size(), 12u);
  for (size_t i = 0; i < 12; ++i) {
    EXPECT_EQ(frames[i]->sequence, i + 1) << "keeps increasing across loops";
    EXPECT_EQ(value_of(*frames[i]), 10 * int(i % 5 + 1)) << i;
  }
  // 40 ms recorded at speed 2: 20 ms apart; a loop of five frames lasts 100 ms.
  EXPECT_NEAR(seconds_between(*frames[0], *frames[4]), 0.080, 0.04);
  EXPECT_NEAR(seconds_between(*frames[0], *frames[10]), 0.200, 0.06);
  // A new rig version at each rig change, looping back to the first rig included.
  EXPECT_EQ(frames[0]->rig_version, 1u);
  EXPECT_EQ(frames[2]->rig_version, 1u);
  EXPECT_EQ(frames[3]->rig_version, 2u);
  EXPECT_EQ(frames[5]->rig_version, 3u);
  EXPECT_EQ(frames[5]->rig, frames[0]->rig);
  EXPECT_NEAR(frames[3]->rig->cameras()[0].T_parent_cam.translation().x(), 1.0, 1e-12);
  // capture_time is the playback time, not 2020's.
  EXPECT_LT(std::chrono::system_clock::now() - frames[0]->capture_time, 10s);
}

TEST(ReplaySource, RateAndNoLoop) {
  TempFolder dir;
  write_recording(dir / "rec", 500ms);  // the recorded timing is ignored at a set rate
  TestConfig config("name: r\ntype: replay\nrecording: rec\nrate_hz: 50\nloop: false\n", dir.str());
  ReplaySource source(config.config);
  Collector collector;
  source.start(collector.callback());
  auto frames = collector.wait_for(5, 2s);
  ASSERT_EQ(frames.size(), 5u);
  EXPECT_NEAR(seconds_between(*frames[0], *frames[4]), 0.080, 0.04);
  std::this_thread::sleep_for(60ms);
  EXPECT_EQ(collector.count(), 5u) << "no loop";
  source.stop();
}

TEST(ReplaySource, HandsOnTheRecordedFilesBytes) {
  TempFolder dir;
  write_recording(dir / "rec", 10ms);  // PNG files (the writer encodes the pixels)
  const Recording rec = Recording::open(dir / "rec");
  TestConfig config("name: r\ntype: replay\nrecording: rec\nloop: false\n", dir.str());
  ReplaySource source(config.config);
  Collector collector;
  source.start(collector.callback());
  const auto frames = collector.wait_for(2, 2s);
  source.stop();
  ASSERT_GE(frames.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    ASSERT_EQ(frames[i]->encoded.size(), 1u);
    EXPECT_EQ(frames[i]->encoded[0].format, "png");
    ASSERT_TRUE(frames[i]->encoded[0].bytes);
    std::ifstream in(dir / ("rec/" + rec.frames[i].image_files[0]), std::ios::binary);
    const std::vector<uint8_t> file{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_EQ(*frames[i]->encoded[0].bytes, file) << "a recording of the replay stores the same bytes";
  }
}

TEST(ReplaySource, CorruptImageIsCountedAndSkipped) {
  TempFolder dir;
  write_recording(dir / "rec", 10ms);
  const Recording rec = Recording::open(dir / "rec");
  std::ofstream(dir / ("rec/" + rec.frames[1].image_files[0]), std::ios::trunc) << "garbage";
  TestConfig config("name: r\ntype: replay\nrecording: rec\nloop: false\n", dir.str());
  ReplaySource source(config.config);
  Collector collector;
  source.start(collector.callback());
  collector.wait_for(4, 2s);
  std::this_thread::sleep_for(30ms);
  source.stop();
  const auto frames = collector.wait_for(4, 0ms);
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_EQ(value_of(*frames[1]), 30) << "frame 2 skipped";
  const SourceHealth health = source.health();
  EXPECT_EQ(health.errors, 1u);
  EXPECT_EQ(health.frames, 4u);
  EXPECT_TRUE(contains(health.message, rec.frames[1].image_files[0])) << health.message;
}

TEST(ReplaySource, ErrorsNameFileLineAndKey) {
  TempFolder dir;
  write_recording(dir / "rec", 10ms);
  const auto error = [&](const std::string& yaml) {
    return config_error([&] {
      TestConfig config(yaml, dir.str());
      ReplaySource source(config.config);
    });
  };
  std::string e = error("name: r\ntype: replay\nrecording: missing\n");
  EXPECT_TRUE(contains(e, "daemon.yaml:3")) << e;
  EXPECT_TRUE(contains(e, "sources[0].recording")) << e;
  EXPECT_TRUE(contains(e, "no such recording folder")) << e;
  e = error("name: r\ntype: replay\nrecording: rec\nspeed: 0\n");
  EXPECT_TRUE(contains(e, "daemon.yaml:4")) << e;
  EXPECT_TRUE(contains(e, "speed")) << e;
  e = error("name: r\ntype: replay\nrecording: rec\nloop: maybe\n");
  EXPECT_TRUE(contains(e, "loop")) << e;
  e = error("name: r\ntype: replay\nrecording: rec\nrepeat: true\n");
  EXPECT_TRUE(contains(e, "repeat")) << e;
  // A broken index names its own file and line.
  std::ofstream(dir / "rec/frames.csv", std::ios::app) << "x,1,0,\n";
  e = error("name: r\ntype: replay\nrecording: rec\n");
  EXPECT_TRUE(contains(e, "frames.csv:7")) << e;
}

}  // namespace
}  // namespace omniview
