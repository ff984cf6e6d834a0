// The real `omniview` binary, run as a user would: help, usage errors, an unreachable
// server, and every client command against a fake omniviewd in this process.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/cli_client/fake_omniviewd.h"
#include "server/recording/recording.h"

namespace {

namespace fs = std::filesystem;
using omniview::testing::FakeOmniviewd;

struct Result {
  int exit_code;
  std::string output;  // stdout and stderr
};

Result run(const std::string& args) {
  const std::string cmd = "env -u OMNIVIEW_SERVER -u OMNIVIEW_TOKEN -u OMNIVIEW_TOKEN_FILE " +
                          std::string(OMNIVIEW_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), pipe)) out.append(buf.data(), n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ClientCli, HelpListsEveryCommand) {
  const auto r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* command :
       {"render", "cameras", "views", "ptz", "snapshot", "watch", "show", "stream", "status", "record"}) {
    EXPECT_TRUE(has(r.output, std::string("  ") + command + " ")) << command;
    const auto help = run(std::string(command) + " --help");
    EXPECT_EQ(help.exit_code, 0) << command;
    EXPECT_TRUE(has(help.output, std::string("usage: omniview ") + command)) << help.output;
    if (std::string(command) != "render") {
      EXPECT_TRUE(has(help.output, "--token-file")) << command;
    }
  }
  EXPECT_EQ(run("snapshot -h").exit_code, 0);
}

TEST(ClientCli, UsageErrors) {
  auto r = run("views list --veiw x");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.output, "unknown option --veiw")) << r.output;
  r = run("views frobnicate");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.output, "unknown subcommand 'frobnicate'")) << r.output;
  r = run("snapshot front -o out.bmp");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.output, "jpg, png or raw")) << r.output;
  r = run("ptz front --zoom 0");
  EXPECT_EQ(r.exit_code, 2);
  r = run("stream front -o dir");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.output, "missing --frames")) << r.output;
  r = run("status --token-file /nonexistent/token");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.output, "/nonexistent/token")) << r.output;
}

TEST(ClientCli, UnreachableServer) {
  for (const char* command : {"status", "views list", "cameras", "snapshot front -o x.png", "watch front",
                              "stream front --frames 2 -o unused_dir"}) {
    const auto r = run(std::string(command) + " --server 127.0.0.1:1");
    EXPECT_EQ(r.exit_code, 1) << command;
    EXPECT_TRUE(has(r.output, "cannot reach omniviewd at 127.0.0.1:1 (is it running?")) << command << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists("unused_dir"));
}

class AgainstFake : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("omniview_client_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  Result omniview(const std::string& args) { return run(args + " --server " + fake_.address()); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }

  FakeOmniviewd fake_;
  fs::path dir_;
};

TEST_F(AgainstFake, ViewsListAndGet) {
  auto r = omniview("views list");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "VIEW")) << r.output;
  EXPECT_TRUE(has(r.output, "front")) << r.output;
  EXPECT_TRUE(has(r.output, "fisheye")) << r.output;
  r = omniview("views get front");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "name: front\ntype: perspective\n# revision: 1")) << r.output;
}

TEST_F(AgainstFake, UnknownViewPassesTheServersMessage) {
  const auto r = omniview("views get frnt");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.output, "omniview views: no view 'frnt' (views: front, round)")) << r.output;
}

TEST_F(AgainstFake, CreateFromAFileWithSeveralViews) {
  const auto file = write("views.yaml",
                          "views:\n  - {name: a, type: perspective, hfov_deg: 60}\n"
                          "  - {name: b, type: fisheye}\n");
  const auto r = omniview("views create --file " + file + " --set width=320");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "created view 'a'")) << r.output;
  EXPECT_TRUE(has(r.output, "created view 'b'")) << r.output;
  const auto creates = fake_.creates();
  ASSERT_EQ(creates.size(), 2u);
  EXPECT_DOUBLE_EQ(creates[0].spec().hfov_deg(), 60);
  EXPECT_EQ(creates[0].spec().width(), 320);
  EXPECT_FALSE(creates[0].spec().has_height());
  EXPECT_EQ(creates[1].spec().type(), omniview::v1::FISHEYE);
  EXPECT_FALSE(creates[1].spec().has_hfov_deg());
}

TEST_F(AgainstFake, CreateErrors) {
  auto r = omniview("views create --file " + write("bad.yaml", "name: a\ntype: perspective\nhfvo_deg: 60\n"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.output, "bad.yaml:3")) << r.output;
  EXPECT_TRUE(has(r.output, "hfvo_deg")) << r.output;
  r = omniview("views create --set type=perspective");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.output, "needs a name")) << r.output;
  r = omniview("views create --set name=front");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.output, "view 'front' exists")) << r.output;
}

TEST_F(AgainstFake, UpdateSendsOnlyTheGivenKeys) {
  auto r = omniview("views update front --set hfov=45 --set fusion=blend");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "updated view 'front' (revision 2)")) << r.output;
  // A file names the view it updates.
  r = omniview("views update --file " + write("front.yaml", "name: front\ntype: perspective\nwidth: 800\n"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto updates = fake_.updates();
  ASSERT_EQ(updates.size(), 2u);
  EXPECT_EQ(updates[0].name(), "front");
  EXPECT_DOUBLE_EQ(updates[0].set().hfov_deg(), 45);
  EXPECT_EQ(updates[0].set().fusion(), omniview::v1::BLEND);
  EXPECT_FALSE(updates[0].set().has_width());
  EXPECT_EQ(updates[1].set().width(), 800);
  EXPECT_FALSE(updates[1].set().has_name());  // its own name is no rename
  EXPECT_FALSE(updates[1].set().has_hfov_deg());
}

TEST_F(AgainstFake, DeleteView) {
  auto r = omniview("views delete front");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "deleted view 'front'"));
  EXPECT_EQ(omniview("views get front").exit_code, 1);
}

TEST_F(AgainstFake, PtzAbsoluteAndRelative) {
  auto r = omniview("ptz front --pan 30 --tilt -10 --zoom 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "front: pan 30.00, tilt -10.00, roll 0.00 deg, hfov 53.13 deg (zoom 2.00x)")) << r.output;
  r = omniview("ptz front --relative --pan 5 --zoom 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "pan 35.00")) << r.output;
  EXPECT_TRUE(has(r.output, "(zoom 4.00x)")) << r.output;
  r = omniview("ptz front --dtilt 2.5");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "tilt -7.50")) << r.output;
  const auto updates = fake_.updates();
  ASSERT_EQ(updates.size(), 3u);
  EXPECT_DOUBLE_EQ(updates[0].set().yaw_deg(), 30);
  EXPECT_FALSE(updates[0].set().has_roll_deg());
  EXPECT_DOUBLE_EQ(updates[1].delta().yaw_deg(), 5);
  EXPECT_DOUBLE_EQ(updates[1].delta().zoom(), 2);
  EXPECT_FALSE(updates[1].set().has_yaw_deg());
  EXPECT_DOUBLE_EQ(updates[2].delta().zoom(), 0);  // unchanged
  // No change: prints where it looks.
  r = omniview("ptz front");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "revision 4")) << r.output;
  // Absolute zoom means nothing to a fisheye view.
  r = omniview("ptz round --zoom 2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.output, "fov_deg")) << r.output;
  r = omniview("ptz round --dzoom 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "fov 90.00 deg")) << r.output;
}

TEST_F(AgainstFake, SnapshotChoosesTheEncodingFromTheExtension) {
  for (const auto& [name, encoding] :
       {std::pair{"out.png", omniview::v1::PNG}, std::pair{"out.jpg", omniview::v1::JPEG},
        std::pair{"out.raw", omniview::v1::RAW}}) {
    const auto path = dir_ / name;
    const auto r = omniview("snapshot front -o " + path.string() + " --gray --quality 70");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(has(r.output, "64x32")) << r.output;
    EXPECT_EQ(fake_.last_snapshot().encoding(), encoding);
    EXPECT_TRUE(fake_.last_snapshot().gray());
    EXPECT_EQ(fake_.last_snapshot().quality(), 70);
    EXPECT_EQ(read(path), FakeOmniviewd::make_frame("front", 42, encoding).data());
  }
}

TEST_F(AgainstFake, StreamWritesFramesAndAnIndex) {
  const auto out = dir_ / "frames";
  const auto r = omniview("stream front --frames 5 -o " + out.string() + " --encoding png --rate 10");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "wrote 5 frames")) << r.output;
  EXPECT_EQ(fake_.last_stream().encoding(), omniview::v1::PNG);
  EXPECT_DOUBLE_EQ(fake_.last_stream().max_rate_hz(), 10);
  EXPECT_EQ(read(out / "frame_000001.png"), FakeOmniviewd::make_frame("front", 1, omniview::v1::PNG).data());
  EXPECT_TRUE(fs::exists(out / "frame_000005.png"));
  EXPECT_FALSE(fs::exists(out / "frame_000006.png"));
  std::istringstream csv(read(out / "frames.csv"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(csv, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0].rfind("file,sequence,capture_time,", 0), 0u);
  EXPECT_EQ(lines[5].rfind("frame_000005.png,6,", 0), 0u) << lines[5];  // sequence 5 was skipped
}

TEST_F(AgainstFake, StreamRefusesAFolderWithFilesUnlessForced) {
  const auto out = dir_ / "used";
  fs::create_directories(out);
  std::ofstream(out / "frames.csv") << "another run\n";
  auto r = omniview("stream front --frames 2 -o " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(has(r.output, "is not empty")) << r.output;
  EXPECT_TRUE(has(r.output, "--force")) << r.output;
  EXPECT_EQ(read(out / "frames.csv"), "another run\n");
  r = omniview("stream front --frames 2 --force -o " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "wrote 2 frames")) << r.output;
}

TEST_F(AgainstFake, ConnectionOptionsMayComeBeforeTheCommand) {
  auto r = run("--server " + fake_.address() + " views list");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "front")) << r.output;
  r = run("--server=" + fake_.address() + " --timeout 5 status");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = run("--frames 3 status");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(has(r.output, "only connection options may come first")) << r.output;
  r = run("--server " + fake_.address());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(has(r.output, "missing COMMAND")) << r.output;
}

TEST_F(AgainstFake, WatchPrintsRatesAndSkips) {
  const auto r = omniview("watch front --duration 2.5");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "fps  latency p50")) << r.output;
  EXPECT_TRUE(has(r.output, "64x32 RGB JPEG")) << r.output;
  EXPECT_TRUE(has(r.output, "skipped")) << r.output;
  EXPECT_TRUE(has(r.output, " frames in ")) << r.output;
  EXPECT_FALSE(has(r.output, ", 0 source frames skipped")) << r.output;  // the fake skips every fifth
}

TEST_F(AgainstFake, StatusAndCameras) {
  auto r = omniview("status");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "omniviewd 0.1.0-fake")) << r.output;
  EXPECT_TRUE(has(r.output, "up 1h 2m 5s")) << r.output;
  EXPECT_TRUE(has(r.output, "SOURCE")) << r.output;
  EXPECT_TRUE(has(r.output, "87.5%")) << r.output;
  EXPECT_TRUE(has(r.output, "ipv4:127.0.0.1:40000")) << r.output;
  r = omniview("cameras --details");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "cam_front")) << r.output;
  EXPECT_TRUE(has(r.output, "ds/none")) << r.output;
  EXPECT_TRUE(has(r.output, "intrinsics: [300.0000")) << r.output;
}

TEST_F(AgainstFake, RecordWritesARecording) {
  const auto out = dir_ / "rec";
  auto r = omniview("record -o " + out.string() + " --frames 3");
  if (has(r.output, "without recording support")) GTEST_SKIP() << "built without omniview_recording";
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "recorded 3 frame sets, skipped 0, of source 'sim'")) << r.output;
  EXPECT_TRUE(fs::exists(out / "recording.yaml"));
  EXPECT_TRUE(fs::exists(out / "rig.yaml"));
  std::istringstream csv(read(out / "frames.csv"));
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_GE(lines, 3);
  // What the replay source reads back: the rig, every frame, the raw image stored as PNG.
  const auto recording = omniview::Recording::open(out.string());
  EXPECT_EQ(recording.source_name, "sim");
  ASSERT_EQ(recording.frames.size(), 3u);
  EXPECT_EQ(recording.frames[1].sequence, 2u);
  ASSERT_EQ(recording.rigs.size(), 1u);
  EXPECT_EQ(recording.rigs[0]->cameras().size(), 1u);
  for (const auto& frame : recording.frames) {
    const auto images = recording.load_images(frame);
    ASSERT_EQ(images.size(), 1u);
    EXPECT_EQ(images[0].cols, 16);
    EXPECT_EQ(images[0].rows, 12);
  }
  // Not into a folder that holds something.
  r = omniview("record -o " + out.string() + " --frames 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.output, "not an empty folder")) << r.output;
  r = omniview("record -o " + (dir_ / "other").string() + " --source nope --duration 1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.output, "no source 'nope'")) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "other"));
}

class AgainstFakeWithTokens : public AgainstFake {
 protected:
  AgainstFakeWithTokens() {}
  FakeOmniviewd secured_{{{"op-secret", "operator"}, {"view-secret", "viewer"}}};
  Result secured(const std::string& args) { return run(args + " --server " + secured_.address()); }
};

TEST_F(AgainstFakeWithTokens, Tokens) {
  auto r = secured("views list");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.output, "requires a token (missing token): pass --token-file FILE or set OMNIVIEW_TOKEN"))
      << r.output;
  r = secured("views list --token-file " + write("wrong", "nope\n"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.output, "rejected the token from --token-file")) << r.output;
  const auto viewer = write("viewer.token", "view-secret\n");
  EXPECT_EQ(secured("views list --token-file " + viewer).exit_code, 0);
  r = secured("views delete front --token-file " + viewer);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.output, "pass an operator token with --token-file")) << r.output;
  EXPECT_EQ(run("views delete front --server " + secured_.address() + " --token-file " + write("op.token", "op-secret"))
                .exit_code,
            0);
  // The token may come from the environment.
  const std::string cmd = "OMNIVIEW_TOKEN=view-secret " + std::string(OMNIVIEW_CLI) + " status --server " +
                          secured_.address() + " > /dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
}

TEST(ClientCliTls, TrustsTheGivenCaAndChecksTheName) {
  const fs::path dir = fs::temp_directory_path() / ("omniview_tls_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string make_cert =
      "openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=omniview.test "
      "-addext subjectAltName=DNS:omniview.test -keyout " +
      (dir / "key.pem").string() + " -out " + (dir / "cert.pem").string() + " > /dev/null 2>&1";
  if (std::system(make_cert.c_str()) != 0) GTEST_SKIP() << "openssl cannot make a test certificate";
  FakeOmniviewd fake({}, read(dir / "cert.pem"), read(dir / "key.pem"));
  const std::string server = " --server " + fake.address() + " --tls-ca " + (dir / "cert.pem").string();
  auto r = run("status" + server + " --tls-server-name omniview.test");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // The certificate does not name 127.0.0.1.
  r = run("status" + server);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.output, "does --tls-ca hold the CA")) << r.output;
  // Plaintext against a TLS server.
  r = run("status --server " + fake.address());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(has(r.output, "if the daemon uses TLS, pass --tls-ca FILE")) << r.output;
  r = run("status" + server.substr(0, server.find(" --tls-ca")) + " --tls-ca " + (dir / "key.pem").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(has(r.output, "holds no PEM certificate")) << r.output;
  fs::remove_all(dir);
}

}  // namespace
