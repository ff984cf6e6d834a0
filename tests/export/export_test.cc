// `omniview export`: a recording (written by RecordingWriter, as `omniview record` writes
// one: two cameras' JPEG bytes, joints, lidar clouds) exported by the real CLI as MCAP, then
// read back by our reader (core/mcap), by Foxglove's own @mcap/core under Node
// (read_with_mcap_core.sh: indexes, CRCs, counts, every schema decoded with protobufjs) and
// by ffmpeg (a view's H.264 frames, concatenated). A file cut short reads up to its last
// complete record; bad recordings and views fail naming the file or the view.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <opencv2/imgproc.hpp>

#include "core/io/image_codec.h"
#include "core/mcap/mcap_reader.h"
#include "foxglove/omniview_schemas.pb.h"
#include "server/recording/recording.h"
#include "tests/server/daemon_process.h"

namespace omniview::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 20;       // at 10 Hz, the first without images
constexpr int kCloudEvery = 4;    // a cloud with every 4th frame set

// Two 160x120 pinholes 1 m up, looking forward (optical z along the robot's x), a little
// apart and turned 20 deg outwards.
std::shared_ptr<Rig> rig() {
  auto rig = std::make_shared<Rig>();
  for (const char* name : {"left", "right"}) {
    const double side = name[0] == 'l' ? 1 : -1;
    Camera cam;
    cam.name = name;
    cam.width = 160;
    cam.height = 120;
    cam.model = make_camera_model({"pinhole", "radtan", {100, 100, 79.5, 59.5}, {-0.05, 0.01, 0, 0}}, name);
    cam.T_parent_cam = make_pose(Vec3(0, 0.1 * side, 1), (-90 + 20 * side) * M_PI / 180, 0, -M_PI / 2);
    rig->add_camera(cam);
  }
  return rig;
}

// A scene that moves: stripes and a gradient shifting with the frame, per camera.
cv::Mat image(int frame, int camera) {
  cv::Mat m(120, 160, CV_8UC3);
  for (int v = 0; v < m.rows; ++v) {
    for (int u = 0; u < m.cols; ++u) {
      const int s = ((u + 3 * frame + 40 * camera) / 12 + v / 12) % 2;
      m.at<cv::Vec3b>(v, u) = cv::Vec3b(uint8_t(40 + 150 * s), uint8_t(2 * v), uint8_t(u + 40 * camera));
    }
  }
  return m;
}

// A wall 4 m ahead, 2 m wide and tall, in the rig's frame.
std::shared_ptr<PointCloud> wall(std::chrono::system_clock::time_point stamp) {
  auto cloud = std::make_shared<PointCloud>();
  cloud->frame = "base_link";
  cloud->stamp = stamp;
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 40; ++j) {
      cloud->points.emplace_back(4.f, -1.f + i * 0.05f, j * 0.05f);
      cloud->intensity.push_back(float(i + j));
    }
  }
  return cloud;
}

void write_recording(const std::string& folder) {
  RecordingWriter writer(folder, "robot");
  const auto r = rig();
  const auto t0 = std::chrono::system_clock::time_point(std::chrono::seconds(1700000000));
  for (int i = 0; i < kFrames; ++i) {
    FrameSet frames;
    frames.sequence = i + 1;
    frames.capture_time = t0 + std::chrono::milliseconds(100 * i);
    frames.rig = r;
    // The first frame set holds no image (empty ones), as a robot's first one announcing its
    // rig can.
    for (int c = 0; c < 2; ++c) {
      frames.images.push_back(i > 0 ? image(i, c) : cv::Mat());
      frames.encoded.push_back(
          i > 0 ? EncodedImage{"jpeg", std::make_shared<std::vector<uint8_t>>(encode_jpeg(frames.images.back(), 90))}
                : EncodedImage{});
    }
    writer.set_next_joints({{"arm_sh0", 0.01 * i}, {"arm_el0", -0.5}});
    if (i % kCloudEvery == 0) writer.set_next_cloud(wall(frames.capture_time - std::chrono::milliseconds(20)));
    writer.write(frames);
  }
}

// Views in a daemon config, as `--config` reads them (its source's keys are not looked at).
std::string views_config() {
  return "sources:\n  - name: robot\n    type: replay\n    recording: recording\n"
         "views:\n"
         "  - {name: front, type: perspective, width: 192, height: 128, hfov_deg: 100, distance: 4}\n"
         "  - {name: panorama, type: cylindrical, width: 256, height: 96, radius: 4, vfov_deg: 60,\n"
         "     azimuth_span_deg: 120}\n";
}

class Export : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    write_recording(recording());
    dir_->write("views.yaml", views_config());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  static std::string recording() { return (dir_->path() / "recording").string(); }
  static std::string config() { return (dir_->path() / "views.yaml").string(); }
  static std::string out(const std::string& name) { return (dir_->path() / name).string(); }

  // Exports once per file name (the tests share the H.264 export).
  static const mcap::McapContents& exported(const std::string& name, const std::string& options = "") {
    static std::map<std::string, mcap::McapContents> done;
    if (const auto it = done.find(name); it != done.end()) return it->second;
    const auto run = run_process(std::string(OMNIVIEW_CLI) + " export " + recording() + " -o " + out(name) +
                                 " --config " + config() + " " + options);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return done[name] = mcap::read_mcap_file(out(name));
  }

  static TempDir* dir_;
};

TempDir* Export::dir_ = nullptr;

std::map<std::string, uint64_t> counts_by_topic(const mcap::McapContents& m) {
  std::map<std::string, uint64_t> out;
  for (const auto& [id, channel] : m.channels) out[channel.topic] = m.message_counts.count(id) ? m.message_counts.at(id) : 0;
  return out;
}

std::string schema_of(const mcap::McapContents& m, const std::string& topic) {
  for (const auto& [id, channel] : m.channels) {
    if (channel.topic == topic) return m.schemas.at(channel.schema_id).name;
  }
  return "";
}

TEST_F(Export, OurReaderFindsEveryTopicWithAMessagePerFrameSet) {
  const auto& m = exported("h264.mcap");
  ASSERT_TRUE(m.complete) << m.why;
  EXPECT_TRUE(m.has_statistics);
  EXPECT_GE(m.chunk_count, 1u);
  EXPECT_EQ(m.chunk_index_count, m.chunk_count);
  const auto counts = counts_by_topic(m);
  for (const char* camera : {"left", "right"}) {
    const std::string topic = std::string("/cameras/") + camera;
    EXPECT_EQ(counts.at(topic + "/image"), uint64_t(kFrames - 1)) << topic;
    EXPECT_EQ(counts.at(topic + "/calibration"), uint64_t(kFrames - 1)) << topic;
    EXPECT_EQ(schema_of(m, topic + "/image"), "foxglove.CompressedImage");
    EXPECT_EQ(schema_of(m, topic + "/calibration"), "foxglove.CameraCalibration");
  }
  EXPECT_EQ(counts.at("/views/front"), uint64_t(kFrames - 1));
  EXPECT_EQ(counts.at("/views/panorama"), uint64_t(kFrames - 1));
  EXPECT_FALSE(counts.count("/views/panorama/calibration")) << "a panorama is no pinhole";
  EXPECT_EQ(counts.at("/views/front/calibration"), uint64_t(kFrames - 1));
  EXPECT_EQ(schema_of(m, "/views/front"), "foxglove.CompressedVideo");
  EXPECT_GE(counts.at("/tf"), 1u);
  EXPECT_EQ(schema_of(m, "/tf"), "foxglove.FrameTransforms");
  EXPECT_EQ(counts.at("/tf"), uint64_t(kFrames / 10)) << "one a second";
  EXPECT_EQ(counts.at("/cloud"), uint64_t(kFrames / kCloudEvery));
  EXPECT_EQ(schema_of(m, "/cloud"), "foxglove.PointCloud");
  EXPECT_EQ(counts.at("/joint_states"), uint64_t(kFrames));
  EXPECT_EQ(schema_of(m, "/joint_states"), "omniview.JointStates");
  // Log time = publish time = the message's own timestamp.
  int clouds = 0;
  for (const auto& msg : m.messages) {
    EXPECT_EQ(msg.log_time, msg.publish_time);
    if (m.channels.at(msg.channel).topic == "/cloud") {
      // The wall ahead, coloured from the cameras: red, green, blue at 12, 13, 14 of 20 bytes.
      foxglove::PointCloud cloud;
      ASSERT_TRUE(cloud.ParseFromString(msg.data));
      ASSERT_EQ(cloud.point_stride(), 20u);
      ASSERT_EQ(cloud.fields(3).name(), "red");
      size_t coloured = 0, points = cloud.data().size() / 20;
      for (size_t i = 0; i < points; ++i) {
        const char* p = cloud.data().data() + i * 20;
        coloured += (p[12] | p[13] | p[14]) != 0;
      }
      EXPECT_EQ(points, 1600u);
      // The first cloud came with the frame set without images: nothing colours it.
      if (clouds++ == 0) {
        EXPECT_EQ(coloured, 0u);
      } else {
        EXPECT_GT(coloured, points / 2) << "of the wall's points, coloured from the cameras";
      }
    }
    if (m.channels.at(msg.channel).topic != "/views/front") continue;
    foxglove::CompressedVideo video;
    ASSERT_TRUE(video.ParseFromString(msg.data));
    EXPECT_EQ(uint64_t(video.timestamp().seconds()) * 1000000000ull + uint64_t(video.timestamp().nanos()), msg.log_time);
    EXPECT_EQ(video.format(), "h264");
    EXPECT_EQ(video.frame_id(), "view/front/optical");
  }
}

// Foxglove's reader: every line of read_with_mcap_core.cjs' report against our own reading.
TEST_F(Export, FoxglovesMcapCoreReadsIndexesAndDecodesEverySchema) {
  const auto& m = exported("h264.mcap");
  const auto run = run_process("bash " + std::string(OMNIVIEW_SOURCE_DIR) + "/tests/export/read_with_mcap_core.sh " +
                               out("h264.mcap"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::istringstream lines(run.output);
  std::map<std::string, uint64_t> counts;
  std::set<std::string> decoded, schemas;
  std::string line;
  uint64_t start = 0, end = 0;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind == "channel") {
      std::string id, topic, schema, encoding;
      uint64_t n = 0;
      words >> id >> topic >> schema >> encoding >> n;
      counts[topic] = n;
      EXPECT_EQ(encoding, "protobuf") << line;
    } else if (kind == "schema") {
      std::string id, name, encoding;
      words >> id >> name >> encoding;
      schemas.insert(name);
      EXPECT_EQ(encoding, "protobuf") << line;
    } else if (kind == "decoded") {
      std::string name;
      words >> name;
      decoded.insert(name);
    } else if (kind == "statistics") {
      uint64_t messages = 0;
      words >> messages >> start >> end;
      EXPECT_EQ(messages, m.messages.size());
    }
  }
  EXPECT_EQ(counts, counts_by_topic(m)) << run.output;
  EXPECT_EQ(schemas, decoded) << "a schema whose message did not decode:\n" << run.output;
  for (const char* s : {"foxglove.CompressedImage", "foxglove.CompressedVideo", "foxglove.CameraCalibration",
                        "foxglove.FrameTransforms", "foxglove.PointCloud", "omniview.JointStates"}) {
    EXPECT_TRUE(decoded.count(s)) << s << "\n" << run.output;
  }
  uint64_t first = UINT64_MAX, last = 0;
  for (const auto& msg : m.messages) {
    first = std::min(first, msg.log_time);
    last = std::max(last, msg.log_time);
  }
  EXPECT_EQ(start, first);
  EXPECT_EQ(end, last);
}

TEST_F(Export, FfmpegDecodesAViewsFramesConcatenated) {
  const auto& m = exported("h264.mcap");
  const std::string h264 = out("front.h264");
  std::ofstream file(h264, std::ios::binary);
  int messages = 0;
  for (const auto& msg : m.messages) {
    if (m.channels.at(msg.channel).topic != "/views/front") continue;
    foxglove::CompressedVideo video;
    ASSERT_TRUE(video.ParseFromString(msg.data));
    if (messages == 0) {
      // The first access unit is a key frame with SPS (NAL type 7) and PPS (8).
      EXPECT_NE(video.data().find(std::string("\0\0\1\x67", 4)), std::string::npos);
      EXPECT_NE(video.data().find(std::string("\0\0\1\x68", 4)), std::string::npos);
    }
    file << video.data();
    ++messages;
  }
  file.close();
  ASSERT_EQ(messages, kFrames - 1);
  const auto probe = run_process("ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                                 "stream=nb_read_frames,width,height -of default=noprint_wrappers=1 -f h264 " + h264);
  ASSERT_EQ(probe.exit_code, 0) << probe.output;
  EXPECT_NE(probe.output.find("nb_read_frames=" + std::to_string(kFrames - 1)), std::string::npos) << probe.output;
  EXPECT_NE(probe.output.find("width=192"), std::string::npos) << probe.output;
  const auto decode = run_process("ffmpeg -v error -f h264 -i " + h264 + " -f null -");
  EXPECT_EQ(decode.exit_code, 0) << decode.output;
  EXPECT_EQ(decode.output.find_first_not_of(" \n"), std::string::npos) << "ffmpeg complained:\n" << decode.output;
}

// The README's picture of an export (tests/export/mcap_picture.cc) from this export: every
// topic on its timeline, the views decoded.
TEST_F(Export, ThePictureToolShowsTheViewsAndEveryTopic) {
  exported("h264.mcap");
  const std::string picture = out("picture.jpg");
  const auto run = run_process(std::string(MCAP_PICTURE) + " " + out("h264.mcap") + " " + picture + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream in(picture, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const cv::Mat image = decode_image(bytes);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.cols, 1400);
  // The views' pictures are there: the area under the first title is not the background.
  cv::Mat grey;
  cv::cvtColor(image(cv::Rect(20, 70, 200, 200)), grey, cv::COLOR_BGR2GRAY);
  cv::Scalar mean, deviation;
  cv::meanStdDev(grey, mean, deviation);
  EXPECT_GT(deviation[0], 5) << "a flat area where the first view should be";
  const auto bad = run_process(std::string(MCAP_PICTURE) + " " + out("no-such.mcap") + " " + picture + " 2>&1");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("no-such.mcap"), std::string::npos) << bad.output;
}

TEST_F(Export, JpegViewsAreCompressedImages) {
  const auto& m = exported("jpeg.mcap", "--encoding jpeg --quality 80 --no-clouds");
  ASSERT_TRUE(m.complete) << m.why;
  EXPECT_EQ(schema_of(m, "/views/front"), "foxglove.CompressedImage");
  EXPECT_FALSE(counts_by_topic(m).count("/cloud"));
  for (const auto& msg : m.messages) {
    if (m.channels.at(msg.channel).topic != "/views/panorama") continue;
    foxglove::CompressedImage image;
    ASSERT_TRUE(image.ParseFromString(msg.data));
    EXPECT_EQ(image.format(), "jpeg");
    EXPECT_EQ(image.data().substr(0, 2), "\xff\xd8");
  }
}

TEST_F(Export, AFileCutShortReadsUpToItsLastCompleteRecord) {
  const auto& whole = exported("small_chunks.mcap", "--chunk-kb 16");
  EXPECT_GT(whole.chunk_count, 4u);
  std::ifstream in(out("small_chunks.mcap"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  for (const double keep : {0.3, 0.7, 0.999}) {
    const std::string cut = bytes.substr(0, size_t(bytes.size() * keep));
    const auto m = mcap::read_mcap(cut, "cut");
    EXPECT_FALSE(m.complete);
    EXPECT_LE(m.cut_at, cut.size());
    EXPECT_LE(m.messages.size(), whole.messages.size());
    if (keep > 0.99) {
      EXPECT_EQ(m.messages.size(), whole.messages.size()) << "only the summary was cut";
    }
  }
  const auto m = mcap::read_mcap(bytes.substr(0, bytes.size() * 7 / 10), "cut");
  EXPECT_GT(m.messages.size(), 0u);
}

TEST_F(Export, BadRecordingsFailNamingTheFile) {
  const auto missing = run_process(std::string(OMNIVIEW_CLI) + " export " + out("no-such-recording") + " -o " +
                                   out("missing.mcap"));
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find("no-such-recording"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(out("missing.mcap")));

  // A copy of the recording with one image overwritten by garbage.
  const fs::path copy = dir_->path() / "damaged";
  fs::copy(recording(), copy, fs::copy_options::recursive);
  std::string victim;
  for (const auto& entry : fs::recursive_directory_iterator(copy / "images")) {
    if (entry.is_regular_file() && (victim.empty() || entry.path().string() > victim)) victim = entry.path().string();
  }
  ASSERT_FALSE(victim.empty());
  std::ofstream(victim, std::ios::binary | std::ios::trunc) << "not an image";
  const auto damaged = run_process(std::string(OMNIVIEW_CLI) + " export " + copy.string() + " -o " +
                                   out("damaged.mcap") + " --config " + config());
  EXPECT_EQ(damaged.exit_code, 1) << damaged.output;
  EXPECT_NE(damaged.output.find(fs::path(victim).filename().string()), std::string::npos) << damaged.output;
  EXPECT_FALSE(fs::exists(out("damaged.mcap"))) << "the half-written export is removed";

  // A view the rig cannot place: named before anything is written.
  dir_->write("bad_view.yaml", "name: lost\ntype: perspective\nwidth: 320\nheight: 240\nhfov_deg: 90\n"
                               "frame: no_such_frame\n");
  const auto lost = run_process(std::string(OMNIVIEW_CLI) + " export " + recording() + " -o " + out("lost.mcap") +
                                " --view " + out("bad_view.yaml"));
  EXPECT_EQ(lost.exit_code, 1) << lost.output;
  EXPECT_NE(lost.output.find("view 'lost'"), std::string::npos) << lost.output;
  EXPECT_FALSE(fs::exists(out("lost.mcap")));

  // An odd size is H.264 too, coded one pixel larger (docs/API.md, "Odd sizes").
  dir_->write("odd_view.yaml", "name: odd\ntype: perspective\nwidth: 321\nheight: 241\nhfov_deg: 90\n");
  const auto odd = run_process(std::string(OMNIVIEW_CLI) + " export " + recording() + " -o " + out("odd.mcap") +
                               " --view " + out("odd_view.yaml"));
  EXPECT_EQ(odd.exit_code, 0) << odd.output;
}

// `omniview record --format mcap` straight from a daemon: the daemon's views of the source
// rendered into the file, the intermediate recording gone unless asked to keep it.
TEST(RecordMcap, ADaemonsSourceAndViewsBecomeOneMcapFile) {
  TempDir dir;
  DaemonProcess daemon(dir, example_config(10, "views:\n"
                                               "  - {name: ahead, type: perspective, width: 160, height: 96, hfov_deg: 90}\n"
                                               "  - {name: around, type: cylindrical, width: 256, height: 64}\n"));
  const std::string file = (dir.path() / "run.mcap").string();
  const std::string cli = std::string(OMNIVIEW_CLI) + " record --format mcap --frames 6 --server " + daemon.address();
  const auto run = run_process(cli + " -o " + file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_FALSE(fs::exists(file + ".recording")) << "the intermediate recording was left behind";
  EXPECT_FALSE(fs::exists(file + ".views"));
  const auto m = mcap::read_mcap_file(file);
  const auto counts = counts_by_topic(m);
  for (const char* topic : {"/views/ahead", "/views/around", "/cameras/front/image", "/cameras/back/image", "/tf"}) {
    EXPECT_TRUE(counts.count(topic)) << topic << " missing; topics: " << run.output;
  }
  EXPECT_GE(counts.count("/views/ahead") ? counts.at("/views/ahead") : 0, 5u);
  EXPECT_EQ(schema_of(m, "/views/ahead"), "foxglove.CompressedVideo");

  // Kept on request; an existing file is refused before anything is recorded.
  const std::string kept = (dir.path() / "kept.mcap").string();
  ASSERT_EQ(run_process(cli + " --keep-recording -o " + kept).exit_code, 0);
  EXPECT_TRUE(fs::is_directory(kept + ".recording"));
  EXPECT_TRUE(fs::exists(kept));
  const auto again = run_process(cli + " -o " + file);
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.output.find("exists"), std::string::npos) << again.output;
  const auto bad = run_process(std::string(OMNIVIEW_CLI) + " record --format avi -o x --server " + daemon.address());
  EXPECT_NE(bad.output.find("--format must be 'dir' or 'mcap'"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace omniview::testing
