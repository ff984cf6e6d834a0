// The daemon's H.264 as real players take it (issue 29): the frame rate the SPS declares,
// key frames over RTSP as ffmpeg depayloads them, a prompt first picture for a player that
// drops what it probed (ffplay -fflags nobuffer), and odd-sized views. The players are
// ffmpeg and ffprobe; the test reads the depayloaded byte stream only to count NAL units.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <future>
#include <sstream>
#include <thread>
#include <vector>

#include "tests/server/daemon_process.h"

namespace omniview::testing {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

bool have_ffmpeg() { return std::system("command -v ffmpeg > /dev/null && command -v ffprobe > /dev/null") == 0; }

std::string timeout_prefix(double seconds) {
  return "timeout " + std::to_string(static_cast<int>(seconds * test_time_scale())) + " ";
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// One NAL unit of an Annex-B stream: its type, and for a slice its first macroblock.
struct Nal {
  int type = 0;
  int first_mb = -1;
};

// first_mb_in_slice: the slice header's first field, an unsigned Exp-Golomb code.
int first_mb(const std::string& data, size_t at) {
  int zeros = 0;
  size_t bit = at * 8;
  const auto get = [&](size_t b) { return (static_cast<unsigned char>(data[b / 8]) >> (7 - b % 8)) & 1; };
  while (bit / 8 < data.size() && get(bit) == 0) ++zeros, ++bit;
  int value = 1;
  for (int i = 0; i < zeros && (bit + 1) / 8 < data.size(); ++i) value = value * 2 + get(++bit);
  return value - 1;
}

std::vector<Nal> nal_units(const std::string& data) {
  std::vector<Nal> out;
  for (size_t i = 0; i + 3 < data.size(); ++i) {
    if (data[i] != 0 || data[i + 1] != 0 || data[i + 2] != 1) continue;
    Nal nal;
    nal.type = data[i + 3] & 0x1f;
    if ((nal.type == 1 || nal.type == 5) && i + 4 < data.size()) nal.first_mb = first_mb(data, i + 4);
    out.push_back(nal);
    i += 3;
  }
  return out;
}

// A daemon on the example images at `rate_hz` with RTSP on a free port.
struct Served {
  explicit Served(double rate_hz, const std::string& views)
      : port(free_port()),
        daemon(dir, example_config(rate_hz, views + "rtsp: {listen: 127.0.0.1:" + std::to_string(port) + "}\n")) {}
  std::string url(const std::string& view) const { return "rtsp://127.0.0.1:" + std::to_string(port) + "/" + view; }
  TempDir dir;
  int port;
  DaemonProcess daemon;
};

const std::string kFront =
    "views:\n"
    "  - {name: front, type: perspective, width: 640, height: 480, frame: base_link, hfov_deg: 100}\n";

// Finding 1: each new stream's SPS declares the source's rate, however long the view was
// left alone before; a raw stream copied into MP4 lasts as long as it was recorded.
TEST(VideoPlayers, EveryStreamStartDeclaresTheSourcesFrameRate) {
  if (!have_ffmpeg()) GTEST_SKIP() << "ffmpeg is not installed (apt-get install ffmpeg)";
  Served s(10, kFront);
  constexpr int kFrames = 10;
  for (int start = 0; start < 4; ++start) {
    const auto file = s.dir.path() / ("start" + std::to_string(start) + ".h264");
    auto r = run_process(timeout_prefix(20) + OMNIVIEW_CLI + " stream front --encoding h264 --frames " +
                         std::to_string(kFrames) + " -o - --server " + s.daemon.address() + " > " + file.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_process("ffprobe -v error -show_entries stream=r_frame_rate -of csv=p=0 " + file.string() + " 2>&1");
    double num = 0, den = 0;
    ASSERT_EQ(std::sscanf(r.output.c_str(), "%lf/%lf", &num, &den), 2) << r.output;
    if (test_time_scale() == 1) {  // under a sanitizer the render itself is slower than the source
      EXPECT_NEAR(num / den, 10.0, 0.5) << "stream start " << start << ": " << r.output;
    }
    const auto mp4 = s.dir.path() / ("start" + std::to_string(start) + ".mp4");
    r = run_process("ffmpeg -v error -y -i " + file.string() + " -c copy " + mp4.string() + " 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = run_process("ffprobe -v error -show_entries format=duration -of csv=p=0 " + mp4.string() + " 2>&1");
    if (test_time_scale() == 1) {
      EXPECT_NEAR(std::atof(r.output.c_str()), kFrames / 10.0, 0.1 * kFrames / 10.0) << "stream start " << start;
    }
    // Long enough for the view to go idle between the streams (the gap is no frame interval).
    std::this_thread::sleep_for(1500ms);
  }
}

// Finding 2: RTSP as ffmpeg depayloads it: each key frame one SPS/PPS pair before its first
// slice, never between its slices, and nothing ffmpeg cannot decode while another client
// joins (each join makes a key frame).
TEST(VideoPlayers, RtspKeyFramesReachFfmpegWholeWhileOthersJoin) {
  if (!have_ffmpeg()) GTEST_SKIP() << "ffmpeg is not installed (apt-get install ffmpeg)";
  Served s(15, kFront);
  const auto file = s.dir.path() / "rtsp.h264";
  auto recording = std::async(std::launch::async, [&] {
    return run_process(timeout_prefix(20) + "ffmpeg -v error -rtsp_transport tcp -i " + s.url("front") +
                       " -t 4 -c copy -f h264 -y " + file.string() + " 2>&1");
  });
  std::this_thread::sleep_for(1500ms);
  for (int i = 0; i < 2; ++i) {
    run_process(timeout_prefix(10) + "ffprobe -v error -rtsp_transport tcp -read_intervals %+0.5 -show_entries "
                "stream=width -of csv=p=0 " + s.url("front") + " 2>&1");
    std::this_thread::sleep_for(500ms);
  }
  const auto r = recording.get();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto nals = nal_units(read_file(file));
  int key_frames = 0, sps = 0, pps = 0;
  int last_type = 0;
  for (const Nal& nal : nals) {
    if (nal.type == 7) ++sps;
    if (nal.type == 8) ++pps;
    if (nal.type == 5 && nal.first_mb == 0) {
      ++key_frames;
      EXPECT_EQ(sps, 1) << "key frame " << key_frames << ": SPS units before its first slice";
      EXPECT_EQ(pps, 1) << "key frame " << key_frames << ": PPS units before its first slice";
    }
    if ((nal.type == 1 || nal.type == 5) && nal.first_mb > 0) {
      EXPECT_NE(last_type, 7) << "an SPS between two slices of one picture";
      EXPECT_NE(last_type, 8) << "a PPS between two slices of one picture";
    }
    if (nal.type == 1 || nal.type == 5) sps = pps = 0;
    last_type = nal.type;
  }
  EXPECT_GE(key_frames, 2) << "the joins made key frames";
  const auto decoded = run_process("ffmpeg -v error -i " + file.string() + " -f null - 2>&1");
  EXPECT_EQ(decoded.exit_code, 0);
  EXPECT_EQ(decoded.output, "") << "ffmpeg's decoder complained";
}

// Finding 3: a player that drops what it probed (the README's low-latency ffplay: nobuffer,
// a probe of one packet) shows its first picture promptly, not at the periodic key frame
// (10 s): the key frame of PLAY is followed by another one for it.
TEST(VideoPlayers, ANobufferPlayerShowsItsFirstPictureWithinASecondOrSo) {
  if (!have_ffmpeg()) GTEST_SKIP() << "ffmpeg is not installed (apt-get install ffmpeg)";
  Served s(15, kFront);
  // The view's stream already running (another client), as for most joins.
  auto other = std::async(std::launch::async, [&] {
    return run_process(timeout_prefix(20) + "ffmpeg -v error -rtsp_transport tcp -i " + s.url("front") +
                       " -t 5 -f null - 2>&1");
  });
  std::this_thread::sleep_for(1500ms);
  for (int i = 0; i < 2; ++i) {
    const auto start = Clock::now();
    const auto r = run_process(timeout_prefix(15) +
                               "ffmpeg -v verbose -fflags nobuffer -flags low_delay -probesize 32 -rtsp_transport tcp -i " +
                               s.url("front") + " -frames:v 1 -f null - 2>&1");
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_LT(seconds, 2.0 * test_time_scale()) << "join " << i << ": the first picture took " << seconds << " s";
  }
  other.get();
}

}  // namespace
}  // namespace omniview::testing
