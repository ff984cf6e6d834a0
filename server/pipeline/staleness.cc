#include "server/pipeline/staleness.h"

#include <algorithm>
#include <cstdio>

namespace omniview {

Staleness judge_staleness(const std::string& source, const SourceStats& stats, const SourceHealth& health,
                          std::chrono::steady_clock::time_point watched_since,
                          std::chrono::steady_clock::time_point now) {
  if (stats.last_arrival == std::chrono::steady_clock::time_point{}) return {};
  const double silent_s = std::chrono::duration<double>(now - std::max(stats.last_arrival, watched_since)).count();
  const double limit_s = std::max(1.5, 4 * stats.mean_interval_s);
  if (silent_s < limit_s) return {};
  char age[32];  // how old the images shown again are
  std::snprintf(age, sizeof age, "%.1f", std::chrono::duration<double>(now - stats.last_arrival).count());
  Staleness s{true, "no new images from source '" + source + "' for " + age + " s"};
  if (!health.connected) {
    s.reason += ": it is not connected";
    if (!health.message.empty()) s.reason += " (" + health.message + ")";
  } else if (!health.message.empty()) {
    s.reason += " (" + health.message + ")";
  }
  return s;
}

}  // namespace omniview
