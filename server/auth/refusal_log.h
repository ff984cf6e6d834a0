// Which refused calls get a log line: a loop of bad tokens must not flood the log (nor
// hide the rest of it). Per peer host, a burst of lines per window; beyond it refusals are
// counted, and the next line that is written says how many were left out.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>

namespace omniview {

class RefusalLog {
 public:
  using Clock = std::chrono::steady_clock;
  explicit RefusalLog(int burst = 5, Clock::duration window = std::chrono::seconds(10))
      : burst_(burst), window_(window) {}

  // nullopt: stay quiet about this refusal (it is counted). Otherwise write a line, adding
  // that the returned number of refusals from this peer were left out before it.
  std::optional<uint64_t> admit(const std::string& peer, Clock::time_point now = Clock::now());

  // "ipv4:10.0.0.7:53422" -> "ipv4:10.0.0.7": a client that reconnects for every try is
  // still one peer. Other forms (unix:, a name) as they are.
  static std::string peer_host(const std::string& peer);

 private:
  struct Window {
    Clock::time_point start;
    int written = 0;
    uint64_t left_out = 0;
  };
  const int burst_;
  const Clock::duration window_;
  std::mutex mutex_;
  std::map<std::string, Window> peers_;
};

}  // namespace omniview
