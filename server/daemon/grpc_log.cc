#include "server/daemon/grpc_log.h"

#include <grpc/support/log.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <utility>

namespace omniview {
namespace {

constexpr int kLinesPerWindow = 5;
constexpr auto kWindow = std::chrono::seconds(10);

struct SiteBudget {
  std::chrono::steady_clock::time_point window_start;
  int written = 0;
  long left_out = 0;
};

std::mutex& budget_mutex() {
  static std::mutex m;
  return m;
}

// Keyed by the site, not the message: one site's messages differ by peer and port.
std::map<std::pair<std::string, int>, SiteBudget>& budgets() {
  static std::map<std::pair<std::string, int>, SiteBudget> b;
  return b;
}

char severity_letter(gpr_log_severity s) {
  switch (s) {
    case GPR_LOG_SEVERITY_DEBUG: return 'D';
    case GPR_LOG_SEVERITY_INFO: return 'I';
    default: return 'E';
  }
}

void limited_log(gpr_log_func_args* args) {
  const std::string file = args->file ? args->file : "?";
  long left_out = 0;
  {
    std::lock_guard lock(budget_mutex());
    auto& budget = budgets()[{file, args->line}];
    const auto now = std::chrono::steady_clock::now();
    if (now - budget.window_start >= kWindow) {
      left_out = budget.left_out;
      budget = SiteBudget{now, 0, 0};
    }
    if (budget.written >= kLinesPerWindow) {
      ++budget.left_out;
      return;
    }
    ++budget.written;
  }
  // One fprintf per line, so lines of different threads do not interleave.
  if (left_out > 0) {
    std::fprintf(stderr, "omniviewd: gRPC %c %s:%d] %s (and %ld more like it not logged)\n",
                 severity_letter(args->severity), file.c_str(), args->line, args->message, left_out);
  } else {
    std::fprintf(stderr, "omniviewd: gRPC %c %s:%d] %s\n", severity_letter(args->severity), file.c_str(), args->line,
                 args->message);
  }
}

}  // namespace

void limit_grpc_log_rate() { gpr_set_log_function(limited_log); }

}  // namespace omniview
