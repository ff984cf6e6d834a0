// Every way an address reaches the real daemon (the config file, --listen, OMNIVIEW_LISTEN)
// in every spelling: `omniviewd --check` and a real start must agree, and both must apply
// the one exposure rule to the address actually used.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <functional>
#include <future>

#include "daemon_process.h"
#include "server/exposure/exposure_rule.h"

namespace omniview::testing {
namespace {

namespace fs = std::filesystem;

enum class Way { kConfig, kFlag, kEnv };

std::string name(Way way) {
  return way == Way::kConfig ? "config file" : way == Way::kFlag ? "--listen" : "OMNIVIEW_LISTEN";
}

// What a config, --listen or OMNIVIEW_LISTEN blames a refusal on.
std::string blamed(Way way) {
  return way == Way::kConfig ? ".yaml:1: listen: " : way == Way::kFlag ? "--listen: " : "OMNIVIEW_LISTEN: ";
}

struct Outcome {
  int check_exit = -1;
  std::string check_output;
  int start_exit = -1;  // 0: it served (the ready file appeared), then stopped on SIGTERM
  std::string start_output;
};

std::string quoted(const std::string& s) { return "'" + s + "'"; }

// --check, then a real start that is stopped as soon as it serves. `extra` is config YAML
// (tls, tokens, allow_insecure_remote) appended to the example config.
Outcome try_way(const TempDir& dir, Way way, const std::string& address, const std::string& extra = "") {
  std::string config = example_config(10, extra);
  std::string prefix, flag;
  if (way == Way::kConfig) config.replace(0, config.find('\n'), "listen: " + quoted(address));
  if (way == Way::kFlag) flag = " --listen " + quoted(address);
  if (way == Way::kEnv) prefix = "OMNIVIEW_LISTEN=" + quoted(address) + " ";
  static std::atomic<int> runs{0};
  const std::string tag = std::to_string(++runs);
  const std::string file = dir.write("way" + tag + ".yaml", config);
  const fs::path ready = dir.path() / ("way" + tag + ".ready");
  Outcome o;
  const auto check = run_process(prefix + OMNIVIEWD + " --check --config " + file + flag);
  o.check_exit = check.exit_code;
  o.check_output = check.output;
  const int tries = static_cast<int>(300 * test_time_scale());  // 0.1 s each
  const std::string start = prefix + OMNIVIEWD + " --config " + file + flag + " --ready-file " + ready.string();
  const std::string script = dir.write(
      "way" + tag + ".sh", start + " & p=$!\nfor i in $(seq " + std::to_string(tries) + "); do\n"
                "  if [ -s " + ready.string() + " ]; then kill $p; wait $p; echo SERVED; exit 0; fi\n"
                "  kill -0 $p 2>/dev/null || { wait $p; exit $?; }\n  sleep 0.1\ndone\nkill -9 $p\nexit 99\n");
  const auto run = run_process("bash " + script);
  o.start_exit = run.exit_code;
  o.start_output = run.output;
  return o;
}

void expect_served(const TempDir& dir, Way way, const std::string& address, const std::string& extra = "") {
  SCOPED_TRACE(name(way) + " " + address);
  const Outcome o = try_way(dir, way, address, extra);
  EXPECT_EQ(o.check_exit, 0) << o.check_output;
  EXPECT_EQ(o.start_exit, 0) << o.start_output;
  EXPECT_NE(o.start_output.find("SERVED"), std::string::npos) << o.start_output;
}

void expect_refused(const TempDir& dir, Way way, const std::string& address, std::vector<std::string> says,
                    const std::string& extra = "") {
  SCOPED_TRACE(name(way) + " " + address);
  const Outcome o = try_way(dir, way, address, extra);
  for (const auto& [exit, output] : {std::pair{o.check_exit, o.check_output}, {o.start_exit, o.start_output}}) {
    EXPECT_EQ(exit, 1) << output;
    EXPECT_NE(output.find(blamed(way)), std::string::npos) << "blames the " << name(way) << ":\n" << output;
    for (const auto& words : says) EXPECT_NE(output.find(words), std::string::npos) << output;
    EXPECT_EQ(output.find("SERVED"), std::string::npos) << output;
  }
}

constexpr Way kWays[] = {Way::kConfig, Way::kFlag, Way::kEnv};

// Runs the checks a few at a time: each is a --check and a start of a separate process,
// and a table of them one by one would take minutes on a loaded machine.
class Parallel {
 public:
  ~Parallel() { wait(); }
  void add(std::function<void()> run) {
    if (running_.size() >= 6) wait();
    running_.push_back(std::async(std::launch::async, std::move(run)));
  }
  void wait() {
    for (auto& r : running_) r.get();
    running_.clear();
  }

 private:
  std::vector<std::future<void>> running_;
};

TEST(Exposure, WildcardsInEverySpellingAreRefusedWithoutTlsAndTokens) {
  TempDir dir;
  Parallel runs;
  for (const Way way : kWays) {
    for (const std::string address : {"0.0.0.0:0", "0:0", "[::]:0", "[0::0]:0", "[::ffff:0.0.0.0]:0"}) {
      runs.add([&dir, way, address] {
        expect_refused(dir, way, address, {"'" + address + "' is reachable from other machines", "neither tls nor tokens"});
      });
    }
    // A form error, caught before gRPC guesses.
    runs.add([&dir, way] { expect_refused(dir, way, ":0", {"names no host"}); });
  }
}

TEST(Exposure, LoopbackInEverySpellingServes) {
  TempDir dir;
  Parallel runs;
  for (const Way way : kWays) {
    for (const std::string address : {"127.0.0.1:0", "[::1]:0", "localhost:0", "[::ffff:127.0.0.1]:0"}) {
      runs.add([&dir, way, address] { expect_served(dir, way, address); });
    }
  }
}

TEST(Exposure, TheOverrideIsJudgedNotTheFile) {
  TempDir dir;
  // The file says a wildcard, the flag or the variable says loopback: it serves on loopback.
  std::string config = example_config(10);
  config.replace(0, config.find('\n'), "listen: 0.0.0.0:0");
  const std::string file = dir.write("wild.yaml", config);
  for (const std::string prefix : {"", "OMNIVIEW_LISTEN=127.0.0.1:0 "}) {
    const std::string flag = prefix.empty() ? " --listen 127.0.0.1:0" : "";
    const auto check = run_process(prefix + OMNIVIEWD + " --check --config " + file + flag);
    EXPECT_EQ(check.exit_code, 0) << check.output;
  }
  DaemonProcess daemon(dir, config, {"--listen", "127.0.0.1:0"});
  EXPECT_EQ(daemon.address().rfind("127.0.0.1:", 0), 0u) << daemon.address();
  // The flag wins over the variable.
  const auto both = run_process("OMNIVIEW_LISTEN=0.0.0.0:0 " + std::string(OMNIVIEWD) + " --check --config " + file +
                                " --listen 127.0.0.1:0");
  EXPECT_EQ(both.exit_code, 0) << both.output;
  const auto env_only = run_process("OMNIVIEW_LISTEN=127.0.0.1:0 " + std::string(OMNIVIEWD) + " --check --config " +
                                    file + " --listen 0.0.0.0:0");
  EXPECT_EQ(env_only.exit_code, 1) << env_only.output;
  EXPECT_NE(env_only.output.find("--listen: '0.0.0.0:0' is reachable"), std::string::npos) << env_only.output;
}

TEST(Exposure, GuardsOrTheOptOutLetAWildcardServe) {
  TempDir dir;
  const auto certs = dir.path() / "certs";
  ASSERT_EQ(std::system(("bash " OMNIVIEW_SOURCE_DIR "/scripts/make-test-certs.sh " + certs.string() + " > /dev/null").c_str()), 0);
  const std::string tls = "tls: {cert: " + (certs / "server.crt").string() + ", key: " + (certs / "server.key").string() + "}\n";
  const std::string tokens = "tokens: [{role: operator, token: operator-secret-1}]\n";
  Parallel runs;
  for (const Way way : kWays) {
    runs.add([&, way] { expect_served(dir, way, "0.0.0.0:0", tls + tokens); });
    runs.add([&, way] { expect_refused(dir, way, "[::]:0", {"there is no tls"}, tokens); });
    runs.add([&, way] { expect_refused(dir, way, "[::]:0", {"there are no tokens"}, tls); });
  }
  runs.add([&] { expect_served(dir, Way::kFlag, "[::]:0", "allow_insecure_remote: true\n"); });
}

TEST(Exposure, HostNamesAreResolvedAndJudgedByEveryAddress) {
  TempDir dir;
  char host[256] = {};
  ASSERT_EQ(::gethostname(host, sizeof host - 1), 0);
  std::string error;
  const auto numbers = resolve_host(host, &error);
  // This machine's own name: refused if it stands for any address another machine can use.
  const bool remote = exposure_refusal({std::string(host) + ":0"}) != "";
  Parallel runs;
  for (const Way way : kWays) {
    runs.add([&, way] {
      if (numbers.empty()) {
        expect_refused(dir, way, std::string(host) + ":0", {"does not resolve"});
      } else if (remote) {
        expect_refused(dir, way, std::string(host) + ":0", {"is reachable from other machines"});
      } else {
        expect_served(dir, way, std::string(host) + ":0");
      }
      expect_refused(dir, way, "no-such-host.invalid:0", {"does not resolve"});
    });
  }
}

TEST(Exposure, AUnixSocketNeedsAFolderOnlyItsOwnerAndGroupCanEnter) {
  TempDir dir;
  const fs::path tight = dir.path() / "tight", loose = dir.path() / "loose";
  fs::create_directories(tight);
  fs::create_directories(loose);
  ASSERT_EQ(::chmod(tight.c_str(), 0750), 0);
  ASSERT_EQ(::chmod(loose.c_str(), 0755), 0);
  Parallel runs;
  for (const Way way : kWays) {
    const std::string tight_socket = "unix:" + (tight / ("o" + std::to_string(static_cast<int>(way)) + ".sock")).string();
    runs.add([&, way, tight_socket] { expect_served(dir, way, tight_socket); });
    runs.add([&, way] { expect_refused(dir, way, "unix:" + (loose / "o.sock").string(), {"every user of this machine can enter"}); });
    runs.add([&, way] { expect_refused(dir, way, "unix-abstract:omniview-test", {"every user of this machine can connect"}); });
  }
  runs.wait();
  // Served on the socket, which only the owner and group may use whatever the umask.
  const std::string socket = (tight / "served.sock").string();
  DaemonProcess daemon(dir, example_config(10), {"--listen", "unix:" + socket});
  EXPECT_EQ(daemon.address(), "unix:" + socket);
  struct stat st {};
  ASSERT_EQ(::stat(socket.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & S_IRWXO, 0u);
  auto stub = make_stub(daemon.address());
  v1::Status status;
  EXPECT_TRUE(stub->GetStatus(make_context().get(), {}, &status).ok());
}

}  // namespace
}  // namespace omniview::testing
