// H.264 streams from the real omniviewd in front of the real spot-mock, over real gRPC,
// decoded by a real decoder (libavcodec): picture quality against the RAW frame of the
// same view, clients joining mid-stream and stalling, the CLI's pipe into ffprobe, and the
// errors of bad requests.
#include <cstdio>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "tests/server/daemon_process.h"
#include "tests/spot_mock/spot_mock_process.h"
#include "tests/video/h264_decoder.h"

namespace omniview::testing {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

std::chrono::milliseconds scaled(std::chrono::milliseconds t) {
  return std::chrono::milliseconds(static_cast<long>(t.count() * test_time_scale()));
}

// One mock robot and one daemon for the whole suite: starting them is most of the time.
class H264Stream : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    mock_ = new SpotMockProcess(dir_->path(), {"--scene", "room", "--supersample", "1"});
    std::ostringstream config;
    config
        << "listen: 127.0.0.1:0\n"
        << "sources:\n"
        << "  - {name: spot, type: spot, robot: 127.0.0.1:" << mock_->port() << ", ca_file: " << mock_->certs_dir()
        << "/ca.pem, credentials_file: " << mock_->credentials_file() << ", rate_hz: 15}\n"
        << "views:\n"
        // The shipped front view at 640x480, and the shipped bird's-eye view.
        << "  - {name: front, type: perspective, source: spot, width: 640, height: 480, frame: body,\n"
        << "     pose: {xyz: [0.42, 0, 0], ypr_deg: [0, 27, 0]}, hfov_deg: 115, distance: 3.0, fusion: blend}\n"
        << "  - {name: birdseye, type: birdseye, source: spot, width: 800, height: 800, frame: footprint,\n"
        << "     pose: {ypr_deg: [0, 90, 0]}, height_m: 3.0, hfov_deg: 110, fusion: blend}\n"
        << "  - {name: odd, type: perspective, source: spot, width: 641, height: 480, frame: body, hfov_deg: 90}\n"
        << "  - {name: resized, type: perspective, source: spot, width: 320, height: 240, frame: body, hfov_deg: 90}\n"
        << "  - {name: panned, type: perspective, source: spot, width: 320, height: 240, frame: body, hfov_deg: 90}\n";
    daemon_ = new DaemonProcess(*dir_, config.str());
  }
  static void TearDownTestSuite() {
    delete daemon_;
    delete mock_;
    delete dir_;
  }

  static TempDir* dir_;
  static SpotMockProcess* mock_;
  static DaemonProcess* daemon_;
};
TempDir* H264Stream::dir_ = nullptr;
SpotMockProcess* H264Stream::mock_ = nullptr;
DaemonProcess* H264Stream::daemon_ = nullptr;

struct Received {
  uint64_t sequence = 0;
  uint64_t revision = 0;  // of the view it shows
  bool key_frame = false;
  bool decoded = false;
  std::string data;
  cv::Mat picture;  // I420 as decoded
  int width = 0, height = 0;
  Clock::time_point arrival;
};

// A client reading a stream on its own thread and decoding every frame as it comes, the way
// a player does. `stall()` stops reading (the client's window fills and the daemon's writes
// block); `resume()` reads on.
class VideoClient {
 public:
  VideoClient(const std::string& address, v1::StreamFramesRequest request, bool small_window = false) {
    grpc::ChannelArguments args;
    args.SetMaxReceiveMessageSize(64 << 20);
    args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
    if (small_window) {
      // Flow control bites after a few frames, not after megabytes.
      args.SetInt(GRPC_ARG_HTTP2_BDP_PROBE, 0);
      args.SetInt(GRPC_ARG_HTTP2_STREAM_LOOKAHEAD_BYTES, 1024);
    }
    stub_ = v1::Omniview::NewStub(grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), args));
    context_ = make_context("", 60s);
    reader_ = stub_->StreamFrames(context_.get(), request);
    thread_ = std::thread([this] { run(); });
  }
  ~VideoClient() { finish(); }

  grpc::Status finish() {
    if (thread_.joinable()) {
      context_->TryCancel();
      resume();
      thread_.join();
    }
    return status_;
  }
  void stall() { stalled_ = true; }
  void resume() { stalled_ = false; }
  std::vector<Received> frames() const {
    std::lock_guard lock(mutex_);
    return frames_;
  }
  size_t count() const {
    std::lock_guard lock(mutex_);
    return frames_.size();
  }
  int decode_errors() const {
    std::lock_guard lock(mutex_);
    return decoder_.errors();
  }
  std::string last_error() const {
    std::lock_guard lock(mutex_);
    return decoder_.last_error();
  }
  bool wait_for(size_t n, std::chrono::milliseconds timeout) const {
    const auto deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
      if (count() >= n || done_) return count() >= n;
      std::this_thread::sleep_for(20ms);
    }
    return count() >= n;
  }
  bool done() const { return done_; }

 private:
  void run() {
    v1::Frame f;
    while (true) {
      while (stalled_) std::this_thread::sleep_for(10ms);
      if (!reader_->Read(&f)) break;
      Received r;
      r.sequence = f.sequence();
      r.revision = f.camera().revision();
      r.key_frame = f.key_frame();
      r.data = f.data();
      r.width = f.width();
      r.height = f.height();
      r.arrival = Clock::now();
      std::lock_guard lock(mutex_);
      r.picture = decoder_.decode(r.data);
      r.decoded = !r.picture.empty();
      frames_.push_back(std::move(r));
    }
    status_ = reader_->Finish();
    done_ = true;
  }

  std::unique_ptr<v1::Omniview::Stub> stub_;
  std::unique_ptr<grpc::ClientContext> context_;
  std::unique_ptr<grpc::ClientReader<v1::Frame>> reader_;
  mutable std::mutex mutex_;
  H264Decoder decoder_;
  std::vector<Received> frames_;
  std::atomic<bool> stalled_{false};
  std::atomic<bool> done_{false};
  grpc::Status status_;
  std::thread thread_;
};

v1::StreamFramesRequest h264(const std::string& view, int quality = 0, int kbps = 0) {
  v1::StreamFramesRequest r;
  r.set_view(view);
  r.set_encoding(v1::H264);
  r.set_quality(quality);
  r.set_max_bitrate_kbps(kbps);
  r.set_gray(true);
  return r;
}

// RAW frames of a view, by sequence, read beside a video stream.
class RawClient {
 public:
  RawClient(const std::string& address, const std::string& view) : stub_(make_stub(address)) {
    v1::StreamFramesRequest r;
    r.set_view(view);
    r.set_encoding(v1::RAW);
    r.set_gray(true);
    context_ = make_context("", 60s);
    reader_ = stub_->StreamFrames(context_.get(), r);
    thread_ = std::thread([this] {
      v1::Frame f;
      while (reader_->Read(&f)) {
        std::lock_guard lock(mutex_);
        frames_[f.sequence()] = cv::Mat(f.height(), f.width(), CV_8UC1, const_cast<char*>(f.data().data())).clone();
      }
    });
  }
  ~RawClient() {
    context_->TryCancel();
    thread_.join();
  }
  std::optional<cv::Mat> find(uint64_t sequence) const {
    std::lock_guard lock(mutex_);
    const auto it = frames_.find(sequence);
    if (it == frames_.end()) return std::nullopt;
    return it->second;
  }

 private:
  std::unique_ptr<v1::Omniview::Stub> stub_;
  std::unique_ptr<grpc::ClientContext> context_;
  std::unique_ptr<grpc::ClientReader<v1::Frame>> reader_;
  mutable std::mutex mutex_;
  std::map<uint64_t, cv::Mat> frames_;
  std::thread thread_;
};

// Mean PSNR of the decoded frames against the RAW frames of the same sequence.
double psnr_against_raw(const std::vector<Received>& frames, const RawClient& raw, int* compared) {
  double sum = 0;
  *compared = 0;
  for (const auto& f : frames) {
    const auto original = raw.find(f.sequence);
    if (!f.decoded || !original) continue;
    sum += psnr(H264Decoder::luma(f.picture, f.width, f.height), *original);
    ++*compared;
  }
  return *compared == 0 ? 0 : sum / *compared;
}

TEST_F(H264Stream, DecodesCloseToTheRawFramesAtDefaultQuality) {
  for (const std::string view : {"front", "birdseye"}) {
    RawClient raw(daemon_->address(), view);
    VideoClient video(daemon_->address(), h264(view));
    ASSERT_TRUE(video.wait_for(20, scaled(8000ms))) << view << ": " << video.count() << " frames\n" << daemon_->log();
    std::this_thread::sleep_for(200ms);  // the RAW frames of the same sequences
    const auto frames = video.frames();
    ASSERT_TRUE(frames.front().key_frame) << "a stream starts at a key frame";
    EXPECT_EQ(video.decode_errors(), 0) << video.last_error();
    for (const auto& f : frames) {
      ASSERT_TRUE(f.decoded) << view << " frame " << f.sequence;
      EXPECT_EQ(f.picture.cols, view == "front" ? 640 : 800);
      EXPECT_EQ(f.picture.rows * 2 / 3, view == "front" ? 480 : 800);
    }
    int compared = 0;
    const double db = psnr_against_raw(frames, raw, &compared);
    std::cout << view << ": " << db << " dB over " << compared << " frames\n";
    EXPECT_GE(compared, 10);
    EXPECT_GE(db, 35) << view;
  }
}

TEST_F(H264Stream, AClientJoiningMidStreamDecodesFromItsFirstFrameAndSharesTheEncoder) {
  const auto started = Clock::now();
  VideoClient first(daemon_->address(), h264("front"));
  ASSERT_TRUE(first.wait_for(15, scaled(8000ms))) << daemon_->log();
  // Bounds in frames of the pace this build renders at (a sanitizer's is several times
  // slower than 15 Hz), never below the 1x bounds.
  const auto frame_time = (Clock::now() - started) / 15;
  const auto joined = Clock::now();
  VideoClient second(daemon_->address(), h264("front"));
  ASSERT_TRUE(second.wait_for(10, std::max<std::chrono::milliseconds>(
                                      scaled(3000ms), std::chrono::duration_cast<std::chrono::milliseconds>(30 * frame_time))))
      << second.count() << " frames; first client " << first.count() << ", a frame per "
      << std::chrono::duration_cast<std::chrono::milliseconds>(frame_time).count() << " ms";
  const auto frames = second.frames();
  EXPECT_TRUE(frames.front().key_frame);
  EXPECT_TRUE(frames.front().decoded) << second.last_error();
  // The key frame is made for the joiner at once (with the next frame rendered), not at
  // some periodic interval.
  EXPECT_LT(frames.front().arrival - joined, std::max<Clock::duration>(scaled(1000ms), 3 * frame_time));
  EXPECT_EQ(second.decode_errors(), 0) << second.last_error();
  // One encoder for both: the frames they both got are the same bytes, and the first
  // client got the joiner's key frame too, decodable in its stream.
  std::map<uint64_t, std::string> by_sequence;
  for (const auto& f : first.frames()) by_sequence[f.sequence] = f.data;
  int shared = 0;
  for (const auto& f : frames) {
    const auto it = by_sequence.find(f.sequence);
    if (it == by_sequence.end()) continue;
    EXPECT_EQ(it->second, f.data) << "frame " << f.sequence;
    ++shared;
  }
  EXPECT_GE(shared, 5);
  EXPECT_EQ(first.decode_errors(), 0) << first.last_error();
}

TEST_F(H264Stream, AStalledClientResumesAtAKeyFrameWithoutHurtingOthers) {
  VideoClient steady(daemon_->address(), h264("front"));
  VideoClient stalled(daemon_->address(), h264("front"), /*small_window=*/true);
  ASSERT_TRUE(stalled.wait_for(5, scaled(8000ms))) << daemon_->log();
  stalled.stall();
  const size_t steady_before = steady.count();
  std::this_thread::sleep_for(5s);
  const size_t before_resume = stalled.count();
  stalled.resume();
  ASSERT_TRUE(stalled.wait_for(before_resume + 10, scaled(5000ms)));
  const auto frames = stalled.frames();
  EXPECT_EQ(stalled.decode_errors(), 0) << stalled.last_error();
  // It missed frames (a gap in the sequence), and the first frame after the gap is a key frame.
  bool gap = false;
  for (size_t i = 1; i < frames.size(); ++i) {
    if (frames[i].sequence > frames[i - 1].sequence + 1) {
      gap = true;
      EXPECT_TRUE(frames[i].key_frame) << "frame " << frames[i].sequence << " after a gap from "
                                       << frames[i - 1].sequence;
    }
    EXPECT_TRUE(frames[i].decoded) << frames[i].sequence;
  }
  EXPECT_TRUE(gap) << "the stall cost no frame: the test did not stall the stream";
  // The steady client went on at the source's rate meanwhile, and the stalled one did not
  // turn its stream into key frames (the stalled one asks for one only once it reads again).
  const auto steady_frames = steady.frames();
  // 5 s at 15 Hz: 75 frames in a release build (fewer where the sanitizers slow the render).
  EXPECT_GT(steady_frames.size() - steady_before, 50 / test_time_scale());
  int keys = 0;
  for (size_t i = steady_before; i < steady_frames.size(); ++i) keys += steady_frames[i].key_frame ? 1 : 0;
  EXPECT_LE(keys, 3);
  EXPECT_EQ(steady.decode_errors(), 0) << steady.last_error();
}

TEST_F(H264Stream, AddsLessThanAFrameIntervalOfLatencyOverJpeg) {
  // The same frames as JPEG and as H.264, side by side: when each reached its client.
  std::mutex mutex;
  std::map<uint64_t, Clock::time_point> jpeg_arrivals;
  auto stub = make_stub(daemon_->address());
  v1::StreamFramesRequest jpeg;
  jpeg.set_view("front");
  jpeg.set_encoding(v1::JPEG);
  jpeg.set_gray(true);
  auto context = make_context("", 60s);
  auto reader = stub->StreamFrames(context.get(), jpeg);
  std::thread jpeg_thread([&] {
    v1::Frame f;
    while (reader->Read(&f)) {
      std::lock_guard lock(mutex);
      jpeg_arrivals[f.sequence()] = Clock::now();
    }
  });
  VideoClient video(daemon_->address(), h264("front"));
  const bool got = video.wait_for(45, scaled(10000ms));
  context->TryCancel();
  jpeg_thread.join();
  ASSERT_TRUE(got) << daemon_->log();
  std::vector<double> extra_ms;
  for (const auto& f : video.frames()) {
    const auto it = jpeg_arrivals.find(f.sequence);
    if (it != jpeg_arrivals.end())
      extra_ms.push_back(std::chrono::duration<double, std::milli>(f.arrival - it->second).count());
  }
  ASSERT_GE(extra_ms.size(), 30u);
  std::sort(extra_ms.begin(), extra_ms.end());
  const double p50 = extra_ms[extra_ms.size() / 2];
  std::cout << "H.264 over JPEG, p50: " << p50 << " ms (includes the client's decode of the previous frame)\n";
  EXPECT_LT(p50, 1000.0 / 15 * test_time_scale());  // one frame interval at the source's 15 Hz
}

TEST_F(H264Stream, TheClisPipeIsAnH264StreamThatFfprobeReads) {
  if (std::system("command -v ffprobe > /dev/null") != 0)
    GTEST_SKIP() << "ffprobe is not installed (apt-get install ffmpeg)";
  const auto r = run_process(std::string(OMNIVIEW_CLI) +
                             " stream front --encoding h264 --gray --frames 20 -o - --server " + daemon_->address() +
                             " 2>/dev/null | ffprobe -v error -count_frames -show_entries "
                             "stream=codec_name,width,height,r_frame_rate,nb_read_frames -of csv=p=0 -");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // codec,width,height,rate,frames: players time a raw stream by the rate its SPS declares,
  // which must be the rate frames come at (the source's 15 Hz, as the view measured it when
  // the stream started, which is noisy: well under the API's 60 Hz rate cap that it was).
  int width = 0, height = 0, frames = 0;
  double rate_num = 0, rate_den = 1;
  ASSERT_EQ(std::sscanf(r.output.c_str(), "h264,%d,%d,%lf/%lf,%d", &width, &height, &rate_num, &rate_den, &frames), 5)
      << r.output;
  EXPECT_EQ(width, 640);
  EXPECT_EQ(height, 480);
  EXPECT_EQ(frames, 20);
  const double declared = rate_num / rate_den;
  EXPECT_LE(declared, 30.0) << r.output;  // the view's rate as measured at the start: noisy (18.3 seen)
  // Under a sanitizer the view really comes slower than the source (the render is slower):
  // the declared rate follows it there.
  if (test_time_scale() == 1) {
    EXPECT_GE(declared, 12.0) << r.output;
  }
  EXPECT_GT(declared, 0) << r.output;
}

TEST_F(H264Stream, TheClisFolderHoldsOnePlayableFile) {
  const auto out = dir_->path() / "stream_out";
  const auto r = run_process(std::string(OMNIVIEW_CLI) + " stream birdseye --encoding h264 --frames 10 -o " +
                             out.string() + " --server " + daemon_->address() + " 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream file(out / "stream.h264", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 1000u);
  // Split at the offsets frames.csv gives; every access unit decodes, the first is a key frame.
  std::ifstream csv(out / "frames.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_NE(line.find("offset,bytes,key_frame"), std::string::npos) << line;
  H264Decoder decoder;
  int rows = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 13u) << line;  // ... offset, bytes, key_frame, measured_depth
    EXPECT_EQ(cells[12], "0.000") << "a view with depth: fixed stood on no measured depth";
    const size_t offset = std::stoul(cells[9]), size = std::stoul(cells[10]);
    ASSERT_LE(offset + size, bytes.size());
    if (rows == 0) {
      EXPECT_EQ(cells[11], "1") << "the file starts at a key frame";
    }
    const cv::Mat picture = decoder.decode(bytes.substr(offset, size));
    EXPECT_EQ(picture.cols, 800) << decoder.last_error();
    ++rows;
  }
  EXPECT_EQ(rows, 10);
  EXPECT_EQ(decoder.errors(), 0) << decoder.last_error();
}

TEST_F(H264Stream, BadRequestsAreClearErrors) {
  auto stub = make_stub(daemon_->address());
  const auto refused = [&](v1::StreamFramesRequest r) {
    auto ctx = make_context();
    auto reader = stub->StreamFrames(ctx.get(), r);
    v1::Frame f;
    while (reader->Read(&f)) {
    }
    return reader->Finish();
  };
  auto unknown = h264("front");
  unknown.set_encoding(static_cast<v1::Encoding>(99));
  auto status = refused(unknown);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("unknown encoding 99"), std::string::npos) << status.error_message();
  for (int kbps : {1, -5, 49, 100001, 2000000000}) {
    status = refused(h264("front", 0, kbps));
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << kbps;
    EXPECT_NE(status.error_message().find("max_bitrate_kbps must be 50..100000"), std::string::npos)
        << status.error_message();
  }
  for (int quality : {-1, 101}) {
    status = refused(h264("front", quality));
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << quality;
  }
  auto jpeg_with_bitrate = h264("front", 0, 500);
  jpeg_with_bitrate.set_encoding(v1::JPEG);
  status = refused(jpeg_with_bitrate);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("H264 streams only"), std::string::npos) << status.error_message();

  v1::SnapshotRequest snap;
  snap.set_view("front");
  snap.set_encoding(v1::H264);
  v1::Frame frame;
  status = stub->GetSnapshot(make_context().get(), snap, &frame);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(status.error_message().find("StreamFrames"), std::string::npos) << status.error_message();
}

// A view of an odd side streams too: coded one pixel larger, its last column repeated, the
// frame saying the view's own size (issue 29).
TEST_F(H264Stream, AnOddSizedViewIsCodedOnePixelLargerWithItsEdgeRepeated) {
  VideoClient client(daemon_->address(), h264("odd"));
  ASSERT_TRUE(client.wait_for(5, scaled(8000ms))) << daemon_->log();
  EXPECT_EQ(client.decode_errors(), 0) << client.last_error();
  const auto frames = client.frames();
  ASSERT_FALSE(frames.empty());
  const auto& last = frames.back();
  EXPECT_EQ(last.width, 641);
  EXPECT_EQ(last.height, 480);
  ASSERT_EQ(last.picture.cols, 642) << client.last_error();
  ASSERT_EQ(last.picture.rows, 480 * 3 / 2);
  const cv::Mat grey = H264Decoder::luma(last.picture, 642, 480);
  const double edge_step = cv::norm(grey.col(641), grey.col(640), cv::NORM_L1) / grey.rows;
  EXPECT_LT(edge_step, 3.0) << "the added column repeats the view's last one";
}

TEST_F(H264Stream, AViewResizedMidStreamStartsAgainAtAKeyFrameAtAnySize) {
  VideoClient client(daemon_->address(), h264("resized"));
  ASSERT_TRUE(client.wait_for(5, scaled(8000ms))) << daemon_->log();
  auto stub = make_stub(daemon_->address());
  v1::UpdateViewRequest update;
  update.set_name("resized");
  update.mutable_set()->set_width(480);
  update.mutable_set()->set_height(360);
  v1::View view;
  ASSERT_TRUE(stub->UpdateView(make_context().get(), update, &view).ok());
  const size_t before = client.count();
  ASSERT_TRUE(client.wait_for(before + 8, scaled(4000ms)));
  const auto frames = client.frames();
  bool resized = false;
  for (size_t i = before; i < frames.size(); ++i) {
    if (frames[i].width != 480) continue;
    if (!resized) {
      EXPECT_TRUE(frames[i].key_frame) << "the first frame of the new size is a key frame";
    }
    resized = true;
    EXPECT_EQ(frames[i].picture.cols, 480) << client.last_error();
  }
  EXPECT_TRUE(resized);
  EXPECT_EQ(client.decode_errors(), 0) << client.last_error();

  // An odd width: coded 482 wide, the stream goes on.
  update.mutable_set()->set_width(481);
  ASSERT_TRUE(stub->UpdateView(make_context().get(), update, &view).ok());
  const size_t before_odd = client.count();
  ASSERT_TRUE(client.wait_for(before_odd + 8, scaled(4000ms))) << client.last_error();
  const auto odd_frames = client.frames();
  bool odd = false;
  for (size_t i = before_odd; i < odd_frames.size(); ++i) {
    if (odd_frames[i].width != 481) continue;
    if (!odd) {
      EXPECT_TRUE(odd_frames[i].key_frame) << "the first frame of the new size is a key frame";
    }
    odd = true;
    EXPECT_EQ(odd_frames[i].picture.cols, 482) << client.last_error();
  }
  EXPECT_TRUE(odd);
  EXPECT_EQ(client.decode_errors(), 0) << client.last_error();
  EXPECT_FALSE(client.done());
}

// A joystick's steps while the stream runs: the stream stays whole (every frame decodes:
// a frame of an old view is dropped before it is encoded, or the next one is a key frame),
// its revisions never go back, and once the last UpdateView returned no frame of an older
// view is handed over (docs/API.md, "Streams"): those that arrive after it were counted as
// handed over by then.
TEST_F(H264Stream, AJoystickMidStreamKeepsItDecodableAndNeverShowsAnOlderView) {
  VideoClient client(daemon_->address(), h264("panned"));
  ASSERT_TRUE(client.wait_for(5, scaled(8000ms))) << daemon_->log();
  auto stub = make_stub(daemon_->address());
  v1::UpdateViewRequest update;
  update.set_name("panned");
  update.mutable_delta()->set_yaw_deg(3);
  v1::View view;
  for (int step = 0; step < 10; ++step) {
    ASSERT_TRUE(stub->UpdateView(make_context().get(), update, &view).ok());
    std::this_thread::sleep_for(30ms);  // about a 30 Hz stick
  }
  v1::Status status;
  ASSERT_TRUE(stub->GetStatus(make_context().get(), {}, &status).ok());
  uint64_t handed_over = 0;
  for (const auto& c : status.clients()) {
    if (c.view() == "panned") handed_over = c.frames_sent();
  }
  const size_t after = client.count();
  ASSERT_TRUE(client.wait_for(after + 5, scaled(4000ms)));
  ASSERT_TRUE(client.wait_for(handed_over + 5, scaled(4000ms)));
  const auto frames = client.frames();
  EXPECT_EQ(client.decode_errors(), 0) << client.last_error();
  uint64_t older = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_TRUE(frames[i].decoded) << frames[i].sequence;
    if (i > 0) {
      EXPECT_GE(frames[i].revision, frames[i - 1].revision) << frames[i].sequence;
    }
    older += frames[i].revision < view.revision() ? 1 : 0;
  }
  EXPECT_LE(older, handed_over) << "a frame of an older view was handed over after UpdateView returned";
  EXPECT_EQ(frames.back().revision, view.revision());
}

}  // namespace
}  // namespace omniview::testing
