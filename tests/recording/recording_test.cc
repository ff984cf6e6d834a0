// RecordingWriter / Recording: what is written reads back; damage is reported or tolerated.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "core/io/image_codec.h"
#include "core/io/yaml_reader.h"
#include "server/recording/recording.h"

namespace omniview {
namespace {
namespace fs = std::filesystem;
using std::chrono::milliseconds;

std::shared_ptr<Rig> small_rig(double x = 0) {
  auto rig = std::make_shared<Rig>();
  for (const char* name : {"left", "right"}) {
    Camera cam;
    cam.name = name;
    cam.width = 32;
    cam.height = 24;
    cam.model = make_camera_model({"pinhole", "none", {20, 20, 15.5, 11.5}, {}}, name);
    cam.T_parent_cam = make_pose(Vec3(x, name[0] == 'l' ? 0.1 : -0.1, 1), 0, 0, 0);
    rig->add_camera(cam);
  }
  return rig;
}

cv::Mat pattern(int seed, int type = CV_8UC3) {
  cv::Mat image(24, 32, type);
  cv::RNG rng(seed);  // its own generator: the same seed gives the same image
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  return image;
}

class RecordingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("recording_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string folder() const { return dir_.string(); }

  // Three frame sets 100 ms apart: raw Mats (stored as PNG), the second with JPEG bytes kept.
  void write_three(const std::shared_ptr<Rig>& rig) {
    RecordingWriter writer(folder(), "cam");
    std::vector<uint8_t> jpeg = encode_jpeg(pattern(7), 95);
    for (int i = 0; i < 3; ++i) {
      FrameSet frames;
      frames.sequence = 10 + i;
      frames.capture_time = t0_ + milliseconds(100 * i);
      frames.rig = rig;
      frames.images = {pattern(i), pattern(i + 100, CV_8UC1)};
      if (i == 1) frames.encoded = {{"jpeg", std::make_shared<std::vector<uint8_t>>(jpeg)}, {}};
      writer.write(frames);
    }
    EXPECT_EQ(writer.frames_written(), 3u);
    jpeg_ = jpeg;
  }

  void append(const std::string& file, const std::string& text) {
    std::ofstream out(dir_ / file, std::ios::app | std::ios::binary);
    out << text;
  }

  fs::path dir_;
  std::chrono::system_clock::time_point t0_ = std::chrono::system_clock::time_point(std::chrono::seconds(1700000000));
  std::vector<uint8_t> jpeg_;
};

TEST_F(RecordingTest, RoundTripKeepsPixelsTimesAndJpegBytes) {
  write_three(small_rig());
  const Recording rec = Recording::open(folder());
  EXPECT_EQ(rec.source_name, "cam");
  EXPECT_EQ(rec.camera_names, (std::vector<std::string>{"left", "right"}));
  ASSERT_EQ(rec.rigs.size(), 1u);
  ASSERT_EQ(rec.frames.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(rec.frames[i].sequence, 10u + i);
    EXPECT_EQ(rec.frames[i].capture_time, t0_ + milliseconds(100 * i));
  }
  const auto images = rec.load_images(rec.frames[0]);
  ASSERT_EQ(images.size(), 2u);
  EXPECT_EQ(cv::norm(images[0], pattern(0), cv::NORM_INF), 0) << "PNG is lossless";
  EXPECT_EQ(images[1].type(), CV_8UC1);
  EXPECT_EQ(cv::norm(images[1], pattern(100, CV_8UC1), cv::NORM_INF), 0);
  // The JPEG bytes are stored as given, not re-encoded.
  ASSERT_EQ(fs::path(rec.frames[1].image_files[0]).extension(), ".jpg");
  std::ifstream in(dir_ / rec.frames[1].image_files[0], std::ios::binary);
  const std::vector<uint8_t> stored((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(stored, jpeg_);
  EXPECT_EQ(rec.load_images(rec.frames[1])[0].size(), cv::Size(32, 24));
}

TEST_F(RecordingTest, AbsentCameraStaysAbsent) {
  auto rig = small_rig();
  RecordingWriter again(folder(), "cam");
  std::vector<uint8_t> png = encode_png(pattern(3));
  again.write(1, t0_, *rig, {{"right", "png", png}});
  again.close();
  const Recording rec = Recording::open(folder());
  const auto images = rec.load_images(rec.frames[0]);
  EXPECT_TRUE(images[0].empty());
  EXPECT_EQ(images[1].size(), cv::Size(32, 24));
}

TEST_F(RecordingTest, CutShortReadsUpToLastCompleteLine) {
  write_three(small_rig());
  append("frames.csv", "13,1700000000300000000,0,images/3_0.pn");  // killed mid-line
  const Recording rec = Recording::open(folder());
  EXPECT_EQ(rec.frames.size(), 3u);
}

TEST_F(RecordingTest, MalformedLineNamesFileAndLine) {
  write_three(small_rig());
  append("frames.csv", "13,soon,0,,\n");
  try {
    Recording::open(folder());
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("frames.csv:5: capture_time_ns 'soon'"), std::string::npos) << e.what();
  }
}

TEST_F(RecordingTest, MissingFolderIsConfigError) {
  EXPECT_THROW(Recording::open(folder()), ConfigError);
}

TEST_F(RecordingTest, CorruptImageNamesFile) {
  write_three(small_rig());
  const Recording rec = Recording::open(folder());
  const fs::path file = dir_ / rec.frames[2].image_files[0];
  std::ofstream(file, std::ios::binary | std::ios::trunc) << "not a png";
  try {
    rec.load_images(rec.frames[2]);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(rec.load_images(rec.frames[0]));
}

TEST_F(RecordingTest, ImageOfWrongSizeIsRejected) {
  write_three(small_rig());
  const Recording rec = Recording::open(folder());
  write_image(dir_ / rec.frames[0].image_files[0], cv::Mat(10, 10, CV_8UC3, cv::Scalar(1, 2, 3)));
  EXPECT_THROW(rec.load_images(rec.frames[0]), std::runtime_error);
  // The writer refuses one too.
  RecordingWriter writer((dir_ / "other").string(), "cam");
  FrameSet frames;
  frames.rig = small_rig();
  frames.images = {cv::Mat(10, 10, CV_8UC3), pattern(1)};
  EXPECT_THROW(writer.write(frames), std::invalid_argument);
}

TEST_F(RecordingTest, RigChangeMidRecording) {
  {
    RecordingWriter writer(folder(), "cam");
    const auto a = small_rig(0), b = small_rig(0.5);
    int i = 0;
    for (const auto& rig : {a, a, b, b, a}) {
      FrameSet frames;
      frames.sequence = ++i;
      frames.capture_time = t0_ + milliseconds(10 * i);
      frames.rig = rig;
      frames.images = {pattern(i), pattern(i)};
      writer.write(frames);
    }
  }
  EXPECT_TRUE(fs::exists(dir_ / "rig.yaml"));
  EXPECT_TRUE(fs::exists(dir_ / "rig_1.yaml"));
  const Recording rec = Recording::open(folder());
  ASSERT_EQ(rec.frames.size(), 5u);
  std::vector<size_t> rig_of;
  for (const auto& f : rec.frames) rig_of.push_back(f.rig_index);
  // Going back to the first rig writes it again: a rig file per change, in order.
  EXPECT_EQ(rig_of, (std::vector<size_t>{0, 0, 1, 1, 2}));
  ASSERT_EQ(rec.rigs.size(), 3u);
  EXPECT_NEAR(rec.rigs[1]->cameras()[0].T_parent_cam.translation().x(), 0.5, 1e-12);
}

TEST_F(RecordingTest, WriterRefusesNonEmptyFolder) {
  write_three(small_rig());
  EXPECT_THROW(RecordingWriter(folder(), "cam"), std::runtime_error);
}

TEST(RecordingIndex, ParsesFromStrings) {
  const std::string yaml = "format: omniview-recording\nversion: 1\nsource: s\ncameras: [a, b]\n";
  const auto index = parse_recording_index(
      yaml, "sequence,capture_time_ns,rig,a,b\n1,5,0,images/0_0.png,\n2,7,1,,images/1_1.jpg\n", "rec");
  EXPECT_EQ(index.rig_count, 2u);
  ASSERT_EQ(index.frames.size(), 2u);
  EXPECT_EQ(index.frames[1].image_files[1], "images/1_1.jpg");
  EXPECT_THROW(parse_recording_index(yaml, "sequence,capture_time_ns,rig,a,b\n1,5,0,../x.png,\n", "rec"), ConfigError);
  EXPECT_THROW(parse_recording_index(yaml, "sequence,capture_time_ns,rig,a\n1,5,0,,\n", "rec"), ConfigError);
  EXPECT_THROW(parse_recording_index("format: other\nversion: 1\ncameras: [a]\n", "", "rec"), ConfigError);
}

}  // namespace
}  // namespace omniview

namespace omniview {
namespace {

// The robot's joints go along with their frame sets (joints.csv) and come back per frame;
// frames without any stay without; damage names the file and line.
TEST(RecordingJoints, KeptPerFrameSetAndReadBack) {
  const fs::path dir = fs::temp_directory_path() / ("recording_joints_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const auto rig = small_rig();
  {
    RecordingWriter writer(dir.string(), "robot");
    for (int i = 0; i < 3; ++i) {
      FrameSet frames;
      frames.sequence = i + 1;
      frames.rig = rig;
      frames.images = {pattern(i), pattern(i + 1)};
      if (i != 1) {
        frames.joints = std::make_shared<const std::map<std::string, double>>(
            std::map<std::string, double>{{"fl.kn", -1.5 - i}, {"fl.hy", 0.1234567890123}});
      }
      writer.write(frames);
    }
  }
  const Recording rec = Recording::open(dir.string());
  ASSERT_EQ(rec.frames.size(), 3u);
  ASSERT_TRUE(rec.frames[0].joints);
  EXPECT_EQ(rec.frames[0].joints->at("fl.kn"), -1.5);
  EXPECT_EQ(rec.frames[0].joints->at("fl.hy"), 0.1234567890123) << "positions kept to the last digit";
  EXPECT_FALSE(rec.frames[1].joints);
  ASSERT_TRUE(rec.frames[2].joints);
  EXPECT_EQ(rec.frames[2].joints->at("fl.kn"), -3.5);

  std::vector<RecordingFrame> frames(2);
  parse_recording_joints("frame,joint,position\n0,a,1\n1,b,2\n5,c,3\n1,d,4", "joints.csv", frames);
  EXPECT_EQ(frames[0].joints->at("a"), 1);
  EXPECT_EQ(frames[1].joints->size(), 1u) << "a cut-short last line is ignored";
  try {
    parse_recording_joints("frame,joint,position\n0,a,straight\n", "rec/joints.csv", frames);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("rec/joints.csv:2: position 'straight'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_recording_joints("frame,name,value\n", "joints.csv", frames), ConfigError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace omniview

namespace omniview {
namespace {

// Lidar clouds go along with their frame sets (clouds.csv + clouds/N.pcd) and come back
// with every field and the stamp; frames without stay without; damage names file and line.
TEST(RecordingClouds, KeptPerFrameSetAndReadBack) {
  const fs::path dir = fs::temp_directory_path() / ("recording_clouds_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const auto rig = small_rig();
  auto cloud = std::make_shared<PointCloud>();
  cloud->frame = "velodyne";
  cloud->stamp = std::chrono::system_clock::time_point(std::chrono::nanoseconds(1700000000123456789));
  cloud->points = {{1, 2, 3}, {-4.25f, 5.5f, 0.125f}};
  cloud->time = {0, 0.05f};
  cloud->ring = {3, 15};
  cloud->intensity = {7, 200};
  {
    RecordingWriter writer(dir.string(), "robot");
    for (int i = 0; i < 3; ++i) {
      FrameSet frames;
      frames.sequence = i + 1;
      frames.rig = rig;
      frames.images = {pattern(i), pattern(i + 1)};
      if (i != 1) frames.cloud = cloud;
      writer.write(frames);
    }
  }
  const Recording rec = Recording::open(dir.string());
  ASSERT_TRUE(rec.has_clouds());
  EXPECT_FALSE(rec.load_cloud(rec.frames[1]));
  const auto back = rec.load_cloud(rec.frames[2]);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->frame, "velodyne");
  EXPECT_EQ(back->stamp, cloud->stamp);
  EXPECT_EQ(back->points, cloud->points);
  EXPECT_EQ(back->time, cloud->time);
  EXPECT_EQ(back->ring, cloud->ring);
  EXPECT_EQ(back->intensity, cloud->intensity);
  fs::remove_all(dir);

  std::vector<RecordingFrame> frames(2);
  parse_recording_clouds("frame,stamp_ns,file\n0,5,clouds/0.pcd\n7,5,clouds/7.pcd\n1,5,clouds/1.p", "c.csv", frames);
  EXPECT_EQ(frames[0].cloud_file, "clouds/0.pcd");
  EXPECT_TRUE(frames[1].cloud_file.empty()) << "a cut-short last line is ignored";
  try {
    parse_recording_clouds("frame,stamp_ns,file\n0,5,../../etc/passwd\n", "rec/clouds.csv", frames);
    ADD_FAILURE() << "a path outside clouds/ was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("rec/clouds.csv:2: file '../../etc/passwd'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_recording_clouds("frame,stamp,file\n", "c.csv", frames), ConfigError);
  EXPECT_THROW(parse_recording_clouds("frame,stamp_ns,file\nx,5,clouds/x.pcd\n", "c.csv", frames), ConfigError);
}

}  // namespace
}  // namespace omniview
