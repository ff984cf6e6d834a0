// Views over RTSP (server/rtsp) from the real omniviewd, read by a real RTSP client
// (ffprobe): the right size and rate, the API's tokens as credentials (wrong ones refused),
// views created and deleted through the API appearing and going, and the exposure rule on
// the RTSP address.
#include <gtest/gtest.h>

#include <future>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cctype>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include "tests/server/daemon_process.h"

namespace omniview::testing {
namespace {

using namespace std::chrono_literals;

bool have_ffprobe() { return std::system("command -v ffprobe > /dev/null") == 0; }

// ffprobe reading `seconds` of `url` over TCP: "codec,width,height,rate,frames" or its error.
ProcessResult probe(const std::string& url, double seconds = 1.5) {
  std::ostringstream cmd;
  const bool tls = url.rfind("rtsps:", 0) == 0;  // RTSPS is TCP only
  cmd << "timeout " << static_cast<int>(15 * test_time_scale()) << " ffprobe -v error"
      << (tls ? "" : " -rtsp_transport tcp") << " -count_frames"
      << " -read_intervals %+" << seconds << " -show_entries stream=codec_name,width,height,r_frame_rate,nb_read_frames"
      << " -of csv=p=0 '" << url << "' 2>&1";
  return run_process(cmd.str());
}

struct Probed {
  std::string codec;
  int width = 0, height = 0;
  int frames = 0;
};

// ffprobe's "codec,width,height,rate,frames" line.
std::optional<Probed> parse_probe(const std::string& output) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> cells;
    std::stringstream cells_in(line);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
    if (cells.size() != 5 || cells[0].empty()) continue;
    Probed p;
    p.codec = cells[0];
    p.width = std::atoi(cells[1].c_str());
    p.height = std::atoi(cells[2].c_str());
    p.frames = std::atoi(cells[4].c_str());
    return p;
  }
  return std::nullopt;
}

// Frames per second of `url` over about 2 s, from its packets' time stamps.
double packet_rate(const std::string& url) {
  const auto r = run_process("timeout " + std::to_string(static_cast<int>(15 * test_time_scale())) +
                             " ffprobe -v error -rtsp_transport tcp -read_intervals %+2 -select_streams v"
                             " -show_entries packet=pts_time -of csv=p=0 '" + url + "' 2>&1");
  std::vector<double> times;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty() && (std::isdigit(static_cast<unsigned char>(line[0])) || line[0] == '-')) {
      times.push_back(std::atof(line.c_str()));
    }
  }
  if (times.size() < 3 || times.back() <= times.front()) {
    ADD_FAILURE() << "no packet times from " << url << ":\n" << r.output;
    return 0;
  }
  return (times.size() - 1) / (times.back() - times.front());
}

const std::string kViews =
    "views:\n"
    "  - {name: front, type: perspective, width: 640, height: 480, frame: base_link, hfov_deg: 100}\n"
    "  - {name: pano, type: equirectangular, width: 1024, height: 512, frame: base_link}\n";

TEST(Rtsp, EveryViewIsServedAtItsSizeAndRateAndTheLogNamesItsUrl) {
  if (!have_ffprobe()) GTEST_SKIP() << "ffprobe is not installed (apt-get install ffmpeg)";
  TempDir dir;
  const int port = free_port();
  DaemonProcess daemon(dir, example_config(15, kViews + "rtsp: {listen: 127.0.0.1:" + std::to_string(port) + "}\n"));
  const std::string base = "rtsp://127.0.0.1:" + std::to_string(port);
  EXPECT_NE(daemon.log().find("RTSP (H.264): " + base + "/front"), std::string::npos) << daemon.log();
  EXPECT_NE(daemon.log().find("RTSP (H.264): " + base + "/pano"), std::string::npos) << daemon.log();
  auto r = probe(base + "/front", 1);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  auto stream = parse_probe(r.output);
  ASSERT_TRUE(stream) << r.output;
  EXPECT_EQ(stream->codec, "h264");
  EXPECT_EQ(stream->width, 640);
  EXPECT_EQ(stream->height, 480);
  // The rate, from the frames' RTP time stamps (taken as each frame reaches the media);
  // ffprobe's own r_frame_rate is a guess from the first few.
  // (Slower where the sanitizers slow the render.)
  const double rate = packet_rate(base + "/front");
  EXPECT_LE(rate, 17);
  EXPECT_GE(rate, 13 / test_time_scale());
  // 1 s at 15 Hz: about 15 frames (the first comes with the key frame made for the client).
  EXPECT_GE(stream->frames, 10 / test_time_scale()) << r.output;
  r = probe(base + "/pano", 1);
  stream = parse_probe(r.output);
  ASSERT_TRUE(stream) << r.output;
  EXPECT_EQ(stream->width, 1024);
  EXPECT_EQ(stream->height, 512);
  r = probe(base + "/no_such_view", 1);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("404"), std::string::npos) << r.output;
}

TEST(Rtsp, TheApisTokensAreTheCredentialsAndWrongOnesAreRefused) {
  if (!have_ffprobe()) GTEST_SKIP() << "ffprobe is not installed (apt-get install ffmpeg)";
  TempDir dir;
  const int port = free_port();
  const std::string viewer = "viewer-token-3f9a1c77e2b04d18";
  DaemonProcess daemon(dir, example_config(15, kViews + "tokens:\n  - {role: viewer, token: " + viewer +
                                                   "}\nrtsp: {listen: 127.0.0.1:" + std::to_string(port) + "}\n"));
  const std::string host = "127.0.0.1:" + std::to_string(port) + "/front";
  for (const std::string& url :
       {"rtsp://" + host, "rtsp://omniview:wrong-token@" + host, "rtsp://someone:" + viewer + "@" + host}) {
    const auto r = probe(url, 1);
    EXPECT_NE(r.exit_code, 0) << url << ": " << r.output;
    EXPECT_NE(r.output.find("401"), std::string::npos) << url << ": " << r.output;
  }
  const auto r = probe("rtsp://omniview:" + viewer + "@" + host, 1);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("h264,640,480"), std::string::npos) << r.output;
  EXPECT_EQ(daemon.log().find(viewer), std::string::npos) << "a token in the log:\n" << daemon.log();
}

TEST(Rtsp, WithTlsItSpeaksRtspsOnAnAddressOthersReach) {
  if (!have_ffprobe()) GTEST_SKIP() << "ffprobe is not installed (apt-get install ffmpeg)";
  TempDir dir;
  const auto certs = dir.path() / "certs";
  ASSERT_EQ(std::system(
                ("bash " OMNIVIEW_SOURCE_DIR "/scripts/make-test-certs.sh " + certs.string() + " > /dev/null").c_str()),
            0);
  const int port = free_port();
  const std::string viewer = "viewer-token-8d2e61b0c4a95f37";
  // A wildcard address: allowed because tls and tokens guard it.
  DaemonProcess daemon(dir, example_config(15, kViews + "tls: {cert: " + (certs / "server.crt").string() +
                                                   ", key: " + (certs / "server.key").string() +
                                                   "}\ntokens:\n  - {role: viewer, token: " + viewer +
                                                   "}\nrtsp: {listen: 0.0.0.0:" + std::to_string(port) + "}\n"));
  EXPECT_NE(daemon.log().find("rtsps://HOST:" + std::to_string(port) + "/front"), std::string::npos) << daemon.log();
  const auto r = probe("rtsps://omniview:" + viewer + "@127.0.0.1:" + std::to_string(port) + "/front", 1);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("h264,640,480"), std::string::npos) << r.output;
  const auto wrong = probe("rtsps://omniview:not-the-token@127.0.0.1:" + std::to_string(port) + "/front", 1);
  EXPECT_NE(wrong.output.find("401"), std::string::npos) << wrong.output;
}

TEST(Rtsp, ViewsCreatedAndDeletedThroughTheApiComeAndGo) {
  if (!have_ffprobe()) GTEST_SKIP() << "ffprobe is not installed (apt-get install ffmpeg)";
  TempDir dir;
  const int port = free_port();
  DaemonProcess daemon(dir, example_config(15, kViews + "rtsp: {listen: 127.0.0.1:" + std::to_string(port) + "}\n"));
  auto stub = make_stub(daemon.address());
  v1::CreateViewRequest create;
  create.mutable_spec()->set_name("side");
  create.mutable_spec()->set_type(v1::PERSPECTIVE);
  create.mutable_spec()->set_width(320);
  create.mutable_spec()->set_height(240);
  create.mutable_spec()->set_yaw_deg(90);
  v1::View view;
  ASSERT_TRUE(stub->CreateView(make_context().get(), create, &view).ok());
  std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(700 * test_time_scale())));
  const std::string url = "rtsp://127.0.0.1:" + std::to_string(port) + "/side";
  auto r = probe(url, 1);
  EXPECT_NE(r.output.find("h264,320,240"), std::string::npos) << r.output;
  v1::DeleteViewRequest del;
  del.set_name("side");
  v1::DeleteViewResponse deleted;
  ASSERT_TRUE(stub->DeleteView(make_context().get(), del, &deleted).ok());
  std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(700 * test_time_scale())));
  r = probe(url, 1);
  EXPECT_NE(r.output.find("404"), std::string::npos) << r.output;
}

// A view of an odd side plays, coded one pixel larger (its edge repeated), and never holds
// up the port for others: its DESCRIBE used to wait 20 s for a first frame that never
// came, on the thread that serves every client (issue 29).
TEST(Rtsp, AnOddSizedViewPlaysAndStallsNobody) {
  if (!have_ffprobe()) GTEST_SKIP() << "ffprobe is not installed (apt-get install ffmpeg)";
  TempDir dir;
  const int port = free_port();
  DaemonProcess daemon(dir, example_config(15, kViews + "  - {name: odd, type: perspective, width: 641, height: 361, "
                                                        "frame: base_link, hfov_deg: 90}\n" +
                                                        "rtsp: {listen: 127.0.0.1:" + std::to_string(port) + "}\n"));
  const std::string base = "rtsp://127.0.0.1:" + std::to_string(port);
  auto odd = std::async(std::launch::async, [&] {
    const auto start = std::chrono::steady_clock::now();
    auto r = probe(base + "/odd", 1);
    return std::make_pair(r, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  });
  const auto front = probe(base + "/front", 1);  // meanwhile, another client
  const auto [r, seconds] = odd.get();
  EXPECT_NE(r.output.find("h264,642,362"), std::string::npos) << r.output;
  EXPECT_LT(seconds, 5 * test_time_scale()) << r.output;
  EXPECT_NE(front.output.find("h264,640,480"), std::string::npos) << front.output;
  EXPECT_EQ(daemon.log().find("not served"), std::string::npos) << daemon.log();
}

TEST(Rtsp, AnAddressOthersReachNeedsTlsAndTokensAsTheApiDoes) {
  TempDir dir;
  const std::string config = dir.write("open.yaml", example_config(15, kViews + "rtsp: {listen: 0.0.0.0:8554}\n"));
  const auto r = run_process(std::string(OMNIVIEWD) + " --check --config " + config + " 2>&1");
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("rtsp.listen"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("reachable from other machines"), std::string::npos) << r.output;
  const std::string bad = dir.write("bad.yaml", example_config(15, kViews + "rtsp: {listen: 127.0.0.1:99999}\n"));
  const auto b = run_process(std::string(OMNIVIEWD) + " --check --config " + bad + " 2>&1");
  EXPECT_NE(b.exit_code, 0);
  EXPECT_NE(b.output.find("rtsp.listen"), std::string::npos) << b.output;
}

}  // namespace
}  // namespace omniview::testing
