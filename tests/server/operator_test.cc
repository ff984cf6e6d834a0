// What an operator does with the real daemon and the real CLI: frames piped to a player,
// views that look right by default, coverage warnings, relative paths, replay with the
// robot's joints, views that survive a restart.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/io/image_codec.h"
#include "core/rig/rig.h"
#include "daemon_process.h"
#include "server/recording/recording.h"

namespace omniview::testing {
namespace {

namespace fs = std::filesystem;

std::string file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Splits concatenated JPEGs (an MJPEG pipe) at their start-of-image / end-of-image markers.
// Inside a JPEG's entropy-coded data a 0xFF byte is always stuffed (FF 00), so FF D9 is
// only ever the end marker (these frames carry no thumbnails).
std::vector<std::string> split_jpegs(const std::string& bytes, std::string* leftover) {
  std::vector<std::string> jpegs;
  size_t pos = 0;
  while (pos + 4 <= bytes.size()) {
    if (static_cast<unsigned char>(bytes[pos]) != 0xFF || static_cast<unsigned char>(bytes[pos + 1]) != 0xD8) break;
    const size_t end = bytes.find("\xFF\xD9", pos + 2);
    if (end == std::string::npos) break;
    jpegs.push_back(bytes.substr(pos, end + 2 - pos));
    pos = end + 2;
  }
  if (leftover) *leftover = bytes.substr(pos);
  return jpegs;
}

class Operator : public ::testing::Test {
 protected:
  Operator()
      : daemon_(dir_, example_config(20, "views:\n  - {name: front, type: perspective, width: 320, height: 160}\n")) {}

  // `omniview ARGS --server <the daemon>`; stdout and stderr together.
  ProcessResult cli(const std::string& args) const {
    return run_process(std::string(OMNIVIEW_CLI) + " " + args + " --server " + daemon_.address());
  }
  // The same with stdout into `file`: what comes back is stderr only.
  ProcessResult cli_to_file(const std::string& args, const fs::path& file) const {
    return run_process("{ " + std::string(OMNIVIEW_CLI) + " " + args + " --server " + daemon_.address() + " > " +
                       file.string() + "; }");
  }

  TempDir dir_;
  DaemonProcess daemon_;
};

TEST_F(Operator, StreamToStdoutIsMjpegThatDecodesFrameByFrame) {
  const fs::path out = dir_.path() / "front.mjpg";
  const auto r = cli_to_file("stream front -o - --frames 5", out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "wrote 5 frames to stdout")) << r.output;  // said on stderr
  EXPECT_FALSE(fs::exists(dir_.path() / "-"));
  std::string leftover;
  const auto jpegs = split_jpegs(file_bytes(out), &leftover);
  ASSERT_EQ(jpegs.size(), 5u);
  EXPECT_TRUE(leftover.empty()) << leftover.size() << " bytes that are no JPEG";
  for (const auto& jpeg : jpegs) {
    const cv::Mat image = decode_image(jpeg);
    ASSERT_FALSE(image.empty());
    EXPECT_EQ(image.cols, 320);
    EXPECT_EQ(image.rows, 160);
  }
}

TEST_F(Operator, StreamToAPipeEndsQuietlyWhenTheReaderCloses) {
  // No --frames: it runs until the reader (here `head`) has had enough.
  const auto r = run_process("bash -c 'set -o pipefail; " + std::string(OMNIVIEW_CLI) + " stream front -o - --server " +
                             daemon_.address() + " | head -c 20000 > /dev/null'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "the reader closed the pipe")) << r.output;
}

// `omniview show` on a machine without a display says so and what to do instead.
TEST_F(Operator, ShowWithoutADisplaySaysWhatToDoInstead) {
  const auto r = run_process("env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(OMNIVIEW_CLI) + " show front --server " +
                             daemon_.address());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "no display to open a window on")) << r.output;
  EXPECT_TRUE(has(r.output, "omniview stream front -o - | ffplay -f mjpeg -")) << r.output;
  // A display that is set but gone (a stale ssh -X forwarding): the same, not an abort.
  const auto gone = run_process("env -u WAYLAND_DISPLAY DISPLAY=:987 " + std::string(OMNIVIEW_CLI) + " show front --server " +
                                daemon_.address());
  EXPECT_EQ(gone.exit_code, 1) << gone.output;
  EXPECT_TRUE(has(gone.output, "no display to open a window on (DISPLAY ':987': nothing listens on /tmp/.X11-unix/X987)"))
      << gone.output;
  const auto remote = run_process("env -u WAYLAND_DISPLAY DISPLAY=127.0.0.1:987.0 " + std::string(OMNIVIEW_CLI) +
                                  " show front --server " + daemon_.address());
  EXPECT_EQ(remote.exit_code, 1) << remote.output;
  EXPECT_TRUE(has(remote.output, "nothing answers on 127.0.0.1:6987")) << remote.output;
}

// `omniview cameras` gives each camera's field of view in degrees, as far as its lens sees.
TEST_F(Operator, CamerasShowTheirFieldOfViewInDegrees) {
  const auto r = cli("cameras");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "FOV (deg)")) << r.output;
  EXPECT_TRUE(has(r.output, "210 x 210")) << r.output;  // the example's 210 deg fisheyes
  EXPECT_FALSE(has(r.output, "model ")) << r.output;
  v1::ListCamerasResponse cameras;
  ASSERT_TRUE(make_stub(daemon_.address())->ListCameras(make_context().get(), {}, &cameras).ok());
  ASSERT_EQ(cameras.cameras_size(), 2);
  for (const auto& c : cameras.cameras()) {
    EXPECT_NEAR(c.hfov_deg(), 210, 0.5) << c.name();
    EXPECT_NEAR(c.vfov_deg(), 210, 0.5) << c.name();
  }
}

// A client learns the stream's rules from its first message's metadata (docs/API.md).
TEST_F(Operator, StreamsSayTheirLimitsUpFront) {
  auto stub = make_stub(daemon_.address());
  v1::StreamFramesRequest request;
  request.set_view("front");
  request.set_max_rate_hz(5);
  auto context = make_context();
  auto reader = stub->StreamFrames(context.get(), request);
  v1::Frame frame;
  ASSERT_TRUE(reader->Read(&frame));
  const auto& metadata = context->GetServerInitialMetadata();
  const auto limits = metadata.find("omniview-stream-limits");
  ASSERT_NE(limits, metadata.end());
  const std::string text(limits->second.data(), limits->second.size());
  EXPECT_TRUE(has(text, "delivery=latest-frame-wins")) << text;
  EXPECT_TRUE(has(text, "max_rate_hz=5;")) << text;
  EXPECT_TRUE(has(text, "max_streams_per_connection=8;")) << text;
  context->TryCancel();
  reader->Finish();
}

TEST_F(Operator, SnapshotToStdoutIsOneImage) {
  const fs::path out = dir_.path() / "snap.jpg";
  auto r = cli_to_file("snapshot front -o -", out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "320x160")) << r.output;
  const std::string bytes = file_bytes(out);
  std::string leftover;
  ASSERT_EQ(split_jpegs(bytes, &leftover).size(), 1u);
  EXPECT_TRUE(leftover.empty());
  EXPECT_FALSE(decode_image(bytes).empty());

  const fs::path png = dir_.path() / "snap.png";
  r = cli_to_file("snapshot front -o - --encoding png", png);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_image(png).cols, 320);
}

// Sideways views of two sources: `dark`, whose back lens is exposed a quarter darker than
// its front one (as two real cameras differ), and `even`, the same rig with both lenses
// alike. Each view as a config view with an explicit fusion.
std::string side_views_config(const std::string& darker_back) {
  const std::string rig = example_dir() + "/rig.yaml", front = example_dir() + "/front.jpg";
  std::string config = "listen: 127.0.0.1:0\nsources:\n";
  config += "  - {name: dark, type: images, rig: " + rig + ", images: {front: " + front + ", back: " + darker_back +
            "}, rate_hz: 20}\n";
  config += "  - {name: even, type: images, rig: " + rig + ", images: {front: " + front + ", back: " + example_dir() +
            "/back.jpg}, rate_hz: 20}\nviews:\n";
  for (const char* source : {"dark", "even"}) {
    for (const char* fusion : {"blend", "nearest"}) {
      config += std::string("  - {name: side_") + fusion + "_" + source + ", source: " + source +
                ", type: perspective, width: 320, height: 160, pose: {ypr_deg: [90, 0, 0]}, fusion: " + fusion + "}\n";
    }
  }
  return config;
}

cv::Mat snapshot_png(v1::Omniview::Stub& stub, const std::string& view) {
  v1::SnapshotRequest request;
  request.set_view(view);
  request.set_encoding(v1::PNG);
  v1::Frame frame;
  auto context = make_context();
  const grpc::Status status = stub.GetSnapshot(context.get(), request, &frame);
  EXPECT_TRUE(status.ok()) << status.error_message();
  const std::string& data = frame.data();
  return decode_image(data);
}

// How abruptly the exposure difference between the lenses appears across the view: the
// largest step between neighbouring columns of the column means of (even - dark), in grey
// levels. The scene's own edges cancel out; a hard seam puts the whole difference into one
// step, a blend spreads it over the feather width.
double seam_step(const cv::Mat& even, const cv::Mat& dark) {
  cv::Mat a, b;
  even.convertTo(a, CV_32F);
  dark.convertTo(b, CV_32F);
  if (a.channels() > 1) cv::cvtColor(a, a, cv::COLOR_BGR2GRAY);
  if (b.channels() > 1) cv::cvtColor(b, b, cv::COLOR_BGR2GRAY);
  cv::Mat means;
  cv::reduce(a - b, means, 0, cv::REDUCE_AVG);
  double strongest = 0;
  for (int u = 0; u + 1 < means.cols; ++u) {
    strongest = std::max(strongest, std::abs(double(means.at<float>(0, u + 1) - means.at<float>(0, u))));
  }
  return strongest;
}

TEST(OperatorViews, CreatedViewsBlendLikeTheConfigsViews) {
  TempDir dir;
  cv::Mat back = read_image(example_dir() + "/back.jpg");
  ASSERT_FALSE(back.empty());
  back.convertTo(back, -1, 0.75);
  const std::string darker_back = (dir.path() / "back_darker.png").string();
  write_image(darker_back, back);
  const std::string config = side_views_config(darker_back);
  DaemonProcess daemon(dir, config);
  auto stub = make_stub(daemon.address());
  // Through the API with nothing but a name, a type, a size and a direction.
  v1::CreateViewRequest create;
  create.mutable_spec()->set_name("side");
  create.mutable_spec()->set_type(v1::PERSPECTIVE);
  create.mutable_spec()->set_width(320);
  create.mutable_spec()->set_height(160);
  create.mutable_spec()->set_yaw_deg(90);
  v1::View view;
  auto context = make_context();
  ASSERT_TRUE(stub->CreateView(context.get(), create, &view).ok());
  EXPECT_EQ(view.spec().fusion(), v1::BLEND);
  // Through the CLI from the README's example file.
  const auto r = run_process(std::string(OMNIVIEW_CLI) + " views create --file " + OMNIVIEW_SOURCE_DIR +
                             "/config/examples/views/front_perspective.yaml --set name=left --set yaw_deg=90"
                             " --server " + daemon.address());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, ", blend, revision")) << r.output;

  // The created view (of the first source, `dark`) is the config's blended view.
  const cv::Mat created = snapshot_png(*stub, "side");
  ASSERT_FALSE(created.empty());
  EXPECT_EQ(cv::norm(created, snapshot_png(*stub, "side_blend_dark"), cv::NORM_INF), 0)
      << "a created view renders as the config's blended view";
  // Looking sideways, the two lenses meet in the middle of the view.
  const double seam_nearest = seam_step(snapshot_png(*stub, "side_nearest_even"), snapshot_png(*stub, "side_nearest_dark"));
  const double seam_blend = seam_step(snapshot_png(*stub, "side_blend_even"), created);
  std::cout << "exposure step across the seam (grey levels per column): nearest " << seam_nearest << ", blend "
            << seam_blend << "\n";
  EXPECT_GT(seam_nearest, 5) << "the test sees the seam";
  EXPECT_LT(seam_blend, 0.5 * seam_nearest);  // measured: 5.2 vs 13.7 grey levels (feather_px 24)
}

TEST(OperatorViews, LowCoverageIsSaidByStatusWatchAndEveryFrame) {
  // One 210 deg lens looking forward; a view looking back sees almost nothing of it.
  TempDir dir;
  const std::string rig = dir.write("front_only.yaml", "frame: base_link\ncameras:\n"
      "  - {name: front, camera_model: pinhole, intrinsics: [258.0, 258.0, 511.5, 511.5],\n"
      "     distortion_model: equidistant, distortion_coeffs: [0.02, -0.004, 0.0005, -0.0001],\n"
      "     resolution: [1024, 1024], fov_deg: 210, mount: {xyz: [0.01, 0, 1], ypr_deg: [0, 0, 0]}}\n");
  DaemonProcess daemon(dir, "listen: 127.0.0.1:0\nsources:\n  - {name: one, type: images, rig: " + rig +
                                ", images: {front: " + example_dir() + "/front.jpg}, rate_hz: 20}\n"
                                "views:\n  - {name: ahead, type: perspective, width: 160, height: 80}\n"
                                "  - {name: behind, type: perspective, width: 160, height: 80, pose: {ypr_deg: [180, 0, 0]}, "
                                "hfov_deg: 60}\n");
  const std::string server = " --server " + daemon.address();
  auto r = run_process(std::string(OMNIVIEW_CLI) + " status" + server);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "warning: view 'behind' shows only 0 % of its pixels")) << r.output;
  EXPECT_FALSE(has(r.output, "view 'ahead' shows only")) << r.output;
  r = run_process(std::string(OMNIVIEW_CLI) + " watch behind --duration 1" + server);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "warning: view 'behind' shows only 0 %")) << r.output;

  auto stub = make_stub(daemon.address());
  for (const auto& [view, low] : {std::pair{"behind", true}, std::pair{"ahead", false}}) {
    v1::SnapshotRequest request;
    request.set_view(view);
    v1::Frame frame;
    auto context = make_context();
    ASSERT_TRUE(stub->GetSnapshot(context.get(), request, &frame).ok());
    if (low) {
      EXPECT_LT(frame.coverage(), 0.01) << view;
    } else {
      EXPECT_GT(frame.coverage(), 0.99) << view;
    }
  }
}

// One rule: a path on the command line resolves against the working directory, a path in a
// config against the config file's folder (not the daemon's working directory).
TEST_F(Operator, RelativePathsFollowOneRule) {
  const fs::path work = dir_.path() / "work";
  fs::create_directories(work);
  // As the README has it: record into recordings/lab of where the command runs.
  auto r = run_process("cd " + work.string() + " && " + OMNIVIEW_CLI + " record -o recordings/lab --frames 3 --server " +
                       daemon_.address());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(work / "recordings/lab/recording.yaml")) << r.output;
  // A config next to it names it the same way; the daemon starts elsewhere.
  TempDir replay_dir;
  fs::rename(work / "recordings", replay_dir.path() / "recordings");
  const std::string config = "listen: 127.0.0.1:0\nsources:\n  - {name: lab, type: replay, recording: recordings/lab}\n"
                             "views:\n  - {name: front, type: perspective, width: 160, height: 80}\n";
  DaemonProcess replay(replay_dir, config);
  auto stub = make_stub(replay.address());
  v1::SnapshotRequest request;
  request.set_view("front");
  v1::Frame frame;
  auto context = make_context();
  EXPECT_TRUE(stub->GetSnapshot(context.get(), request, &frame).ok());

  // A path that is not there says where it looked and why there.
  const std::string bad = replay_dir.write("bad.yaml", "listen: 127.0.0.1:0\nsources:\n"
                                                       "  - {name: lab, type: replay, recording: recordings/none}\n");
  r = run_process(std::string(OMNIVIEWD) + " --check --config " + bad);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(has(r.output, "resolves against the config file's folder, " + replay_dir.path().string())) << r.output;
}

cv::Mat snapshot_raw(v1::Omniview::Stub& stub, const std::string& view) {
  v1::SnapshotRequest request;
  request.set_view(view);
  request.set_encoding(v1::RAW);
  v1::Frame frame;
  auto context = make_context();
  const grpc::Status status = stub.GetSnapshot(context.get(), request, &frame);
  EXPECT_TRUE(status.ok()) << status.error_message();
  if (!status.ok()) return {};
  return cv::Mat(frame.height(), frame.width(), frame.channels() == 3 ? CV_8UC3 : CV_8UC1,
                 const_cast<char*>(frame.data().data()))
      .clone();
}

// A replay of the example rig, the spot-like model drawn into a bird's-eye view, `joints`
// from the config.
std::string replay_overlay_config(const fs::path& recording, const std::string& joints) {
  return "listen: 127.0.0.1:0\nsources:\n  - {name: lab, type: replay, recording: " + recording.string() +
         ", rate_hz: 20}\nviews:\n"
         "  - {name: down, type: birdseye, width: 300, height: 300, frame: base_link, height_m: 3, hfov_deg: 60,\n"
         "     overlay: true, overlay_opacity: 1}\n"
         "robot_models:\n  - {source: lab, urdf: " + std::string(OMNIVIEW_SOURCE_DIR) +
         "/config/robots/spot/spot_like.urdf, frame: base_link" + (joints.empty() ? "" : ", joints: " + joints) + "}\n";
}

// A recording keeps the legs' positions; a replay draws them as they were, and a recording
// of that replay keeps them again.
TEST(OperatorReplay, TheRecordedJointsAreDrawn) {
  TempDir dir;
  const std::map<std::string, double> bent{{"fl.hy", 0.8}, {"fl.kn", -1.6}, {"hr.hy", 0.8}, {"hr.kn", -1.6}};
  const fs::path with_joints = dir.path() / "with_joints", without = dir.path() / "without";
  {
    const Rig rig = load_rig_yaml(example_dir() + "/rig.yaml");
    std::vector<RecordedImage> images;
    for (const char* camera : {"front", "back"}) {
      const std::string bytes = file_bytes(example_dir() + "/" + camera + ".jpg");
      images.push_back({camera, "jpeg", std::vector<uint8_t>(bytes.begin(), bytes.end())});
    }
    RecordingWriter a(with_joints.string(), "lab"), b(without.string(), "lab");
    for (uint64_t i = 1; i <= 3; ++i) {
      const auto t = std::chrono::system_clock::now() + std::chrono::milliseconds(50 * i);
      a.set_next_joints(bent);
      a.write(i, t, rig, images);
      b.write(i, t, rig, images);
    }
  }
  ASSERT_TRUE(fs::exists(with_joints / "joints.csv"));

  TempDir replay_dir, reference_dir;
  DaemonProcess replay(replay_dir, replay_overlay_config(with_joints, ""));
  // The same legs from the config, over a recording without joints: what the replay must show.
  DaemonProcess reference(reference_dir,
                          replay_overlay_config(without, "{fl.hy: 0.8, fl.kn: -1.6, hr.hy: 0.8, hr.kn: -1.6}"));
  auto replay_stub = make_stub(replay.address()), reference_stub = make_stub(reference.address());
  const cv::Mat replayed = snapshot_raw(*replay_stub, "down"), expected = snapshot_raw(*reference_stub, "down");
  ASSERT_FALSE(replayed.empty()) << replay.log();
  ASSERT_FALSE(expected.empty()) << reference.log();
  EXPECT_LE(cv::norm(replayed, expected, cv::NORM_INF), 2) << "the replay draws the recorded legs";
  // Nearly straight legs (the knees' limit is -0.25 rad) through the API, over the config's.
  v1::SetJointPositionsRequest straighten;
  for (const char* knee : {"fl.kn", "hr.kn"}) (*straighten.mutable_positions())[knee] = -0.25;
  for (const char* hip : {"fl.hy", "hr.hy"}) (*straighten.mutable_positions())[hip] = 0;
  v1::JointPositions joints;
  const grpc::Status set = reference_stub->SetJointPositions(make_context().get(), straighten, &joints);
  ASSERT_TRUE(set.ok()) << set.error_message();
  const cv::Mat straight = snapshot_raw(*reference_stub, "down");
  EXPECT_GT(cv::norm(replayed, straight, cv::NORM_INF), 50) << "straight legs look different: the test can see legs";

  // `omniview record` of the replay keeps them.
  const fs::path again = dir.path() / "again";
  const auto r = run_process(std::string(OMNIVIEW_CLI) + " record -o " + again.string() + " --frames 2 --server " +
                             replay.address());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Recording recorded = Recording::open(again.string());
  ASSERT_TRUE(recorded.frames[0].joints);
  EXPECT_EQ(*recorded.frames[0].joints, bent);
}

std::map<std::string, std::string> views_yaml(v1::Omniview::Stub& stub) {
  v1::ListViewsResponse response;
  auto context = make_context();
  EXPECT_TRUE(stub.ListViews(context.get(), v1::ListViewsRequest(), &response).ok());
  std::map<std::string, std::string> yaml;
  for (const auto& v : response.views()) yaml[v.spec().name()] = v.yaml();
  return yaml;
}

// `omniview views save` writes what `views_file:` loads: views created and changed at run
// time come back after a restart, exactly as they were.
TEST(OperatorViews, SavedViewsSurviveARestart) {
  TempDir dir;
  const std::string config = example_config(
      20, "views_file: saved_views.yaml\nviews:\n  - {name: front, type: perspective, width: 320, height: 160}\n");
  std::map<std::string, std::string> before;
  {
    DaemonProcess daemon(dir, config);  // no saved_views.yaml yet: just the config's views
    // ... which the start-up log says, naming where it looked.
    EXPECT_TRUE(has(daemon.log(), "views_file '" + (dir.path() / "saved_views.yaml").string() + "' does not exist (yet)"))
        << daemon.log();
    const std::string cli = std::string(OMNIVIEW_CLI) + " --server " + daemon.address() + " ";
    auto r = run_process(cli + "views create --set name=ptz --set type=perspective --set width=200 --set height=100"
                               " --set yaw=45 --set tilt=10");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_process(cli + "views update front --set hfov=70");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_process(cli + "views save " + (dir.path() / "saved_views.yaml").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(has(r.output, "saved 2 views")) << r.output;
    before = views_yaml(*make_stub(daemon.address()));
    EXPECT_EQ(daemon.stop(), 0);
  }
  DaemonProcess restarted(dir, config);
  EXPECT_FALSE(has(restarted.log(), "does not exist")) << restarted.log();
  auto stub = make_stub(restarted.address());
  EXPECT_EQ(views_yaml(*stub), before);
  v1::GetViewRequest get;
  get.set_name("front");
  v1::View front;
  ASSERT_TRUE(stub->GetView(make_context().get(), get, &front).ok());
  EXPECT_DOUBLE_EQ(front.spec().hfov_deg(), 70) << "the saved view replaces the config's of the same name";

  // A damaged file is named with its line, and the daemon does not start.
  dir.write("saved_views.yaml", "views:\n  - {name: ptz, type: perspective, hfov_deg: 500}\n");
  const std::string checked = dir.write("check.yaml", config);
  const auto r = run_process(std::string(OMNIVIEWD) + " --check --config " + checked);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(has(r.output, "saved_views.yaml:2")) << r.output;
}

// docs/API.md's Python examples run as written, against the real daemon.
TEST_F(Operator, TheApiDocsPythonExamplesRun) {
  const std::string doc = file_bytes(fs::path(OMNIVIEW_SOURCE_DIR) / "docs/API.md");
  int examples = 0;
  for (size_t start = doc.find("```python\n"); start != std::string::npos; start = doc.find("```python\n", start)) {
    start += 10;
    const size_t end = doc.find("\n```", start);
    ASSERT_NE(end, std::string::npos);
    const std::string script = dir_.write("example_" + std::to_string(++examples) + ".py", doc.substr(start, end - start));
    const auto r = run_process("cd " + std::string(OMNIVIEW_SOURCE_DIR) + " && OMNIVIEW_SERVER=" + daemon_.address() +
                               " " + OMNIVIEW_DEBIAN_PYTHON + " " + script);
    EXPECT_EQ(r.exit_code, 0) << "docs/API.md Python example " << examples << ":\n" << r.output;
    if (examples == 1) {
      EXPECT_TRUE(has(r.output, "delivery=latest-frame-wins")) << r.output;
      EXPECT_TRUE(has(r.output, "hfov 67.4")) << r.output;  // zoom 1.5 on 90 deg: 2 atan(tan(45)/1.5)
    }
    if (examples == 2) {
      EXPECT_TRUE(has(r.output, "NOT_FOUND - no view named 'no_such_view'")) << r.output;
    }
  }
  EXPECT_EQ(examples, 2);
}

}  // namespace
}  // namespace omniview::testing
