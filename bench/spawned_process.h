// A program the daemon benchmarks start (omniviewd, spot-mock): spawned with its stderr in a
// log file, waited for until it writes its ready file, its CPU time read from /proc, and
// stopped (SIGTERM, reaped) when it goes out of scope.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace omniview::bench {

class SpawnedProcess {
 public:
  // Runs `args` (args[0] the program) with stdout and stderr into `log`; waits up to
  // `timeout` for `ready_file` and keeps its first word (an address) in ready().
  SpawnedProcess(std::vector<std::string> args, const std::filesystem::path& log,
                 const std::filesystem::path& ready_file, std::chrono::seconds timeout = std::chrono::seconds(60)) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    const int failed = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (failed) throw std::runtime_error("cannot start " + args[0]);
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!std::filesystem::exists(ready_file) && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));  // the file's first line written whole
    std::ifstream(ready_file) >> ready_;
    if (ready_.empty()) throw std::runtime_error(args[0] + " did not start; see " + log.string());
  }
  ~SpawnedProcess() {
    kill(pid_, SIGTERM);
    waitpid(pid_, nullptr, 0);
  }
  SpawnedProcess(const SpawnedProcess&) = delete;
  SpawnedProcess& operator=(const SpawnedProcess&) = delete;

  const std::string& ready() const { return ready_; }

  // utime + stime so far, in seconds.
  double cpu_seconds() const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/stat");
    std::string s((std::istreambuf_iterator<char>(in)), {});
    std::istringstream fields(s.substr(s.rfind(')') + 2));
    std::string f;
    double ticks = 0;
    for (int i = 3; i <= 15 && fields >> f; ++i) {
      if (i == 14 || i == 15) ticks += std::stod(f);
    }
    return ticks / double(sysconf(_SC_CLK_TCK));
  }

 private:
  pid_t pid_ = -1;
  std::string ready_;
};

// The p-quantile (0..1) of `v`, nearest rank; 0 when empty.
inline double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * double(v.size())))];
}

}  // namespace omniview::bench
