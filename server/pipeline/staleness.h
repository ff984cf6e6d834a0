// When a source's views are stale: it has delivered nothing new for a while (a camera
// unplugged, a robot out of Wi-Fi range). Its views are then rendered again from its last
// images about once a second and sent marked stale (Frame.stale), so that a client can warn
// the operator instead of showing a frozen picture as if it were live.
#pragma once

#include <chrono>
#include <string>

#include "server/pipeline/source_channel.h"
#include "server/source/source.h"

namespace omniview {

struct Staleness {
  bool stale = false;
  std::string reason;  // for a person: why nothing new comes
};

// How often a silent source's views are sent again (and staleness looked at).
inline constexpr std::chrono::milliseconds kStaleResendInterval{1000};

// Stale when nothing arrived for the longer of 1.5 s and four of the source's usual frame
// intervals (a 0.5 Hz source is not stale 2.1 s after its last frame set), counted from its
// last frame set or from `watched_since`, whichever is later: a source that pulls images
// only while somebody watches (Spot) had no reason to deliver before. A source that has
// delivered nothing yet is not stale: there is nothing to show again.
Staleness judge_staleness(const std::string& source, const SourceStats& stats, const SourceHealth& health,
                          std::chrono::steady_clock::time_point watched_since,
                          std::chrono::steady_clock::time_point now);

}  // namespace omniview
