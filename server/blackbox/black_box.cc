#include "server/blackbox/black_box.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <regex>

namespace omniview {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Frame sets waiting for the disk: a few seconds of a robot, so a slow flush loses nothing.
const TapLimits kQueue{64, size_t{128} << 20};
// How often the watcher looks at the sources' connections.
constexpr std::chrono::milliseconds kWatchInterval{250};
// Write errors (a full disk) are logged at most this often per source.
constexpr std::chrono::seconds kErrorLogInterval{10};
// In a ring's folder while a daemon keeps it: found at start, the last run did not stop cleanly.
constexpr const char* kOpenMarker = ".open";

std::string utc_stamp() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y%m%dT%H%M%SZ", &tm);
  return text;
}

void log(const std::string& line) { std::cerr << "omniviewd: black box: " << line << std::endl; }

std::string describe_span(double seconds) {
  char text[32];
  if (seconds >= 60) {
    std::snprintf(text, sizeof text, "%dm%02ds", int(seconds) / 60, int(seconds) % 60);
  } else {
    std::snprintf(text, sizeof text, "%.1f s", seconds);
  }
  return text;
}

}  // namespace

struct BlackBox::Recorder {
  std::string source;
  mutable std::mutex mutex;  // the ring and the fields below
  std::unique_ptr<BlackBoxRing> ring;
  TapSubscription tap;
  uint64_t not_kept = 0;  // too big for a segment, or a write failed
  std::string message;
  Clock::time_point last_error_log{};
  std::string last_snapshot;
  Clock::time_point last_auto_save{};
  bool was_connected = false;  // watcher thread only
  std::thread writer;
};

void BlackBox::check_folder(const std::string& folder) {
  // The folder, or the nearest folder above it that exists (where it would be made).
  fs::path at = fs::absolute(folder);
  std::error_code ec;
  while (!fs::exists(at, ec) && at.has_parent_path() && at.parent_path() != at) at = at.parent_path();
  if (!fs::is_directory(at, ec)) {
    throw std::runtime_error("cannot create the black box folder '" + folder + "': '" + at.string() +
                             "' is not a folder");
  }
  if (::access(at.c_str(), W_OK | X_OK) != 0) {
    throw std::runtime_error("cannot write in '" + at.string() + "' (for the black box folder '" + folder +
                             "'): " + std::strerror(errno));
  }
}

BlackBox::BlackBox(const BlackBoxConfig& config, Pipeline& pipeline, const std::vector<std::string>& sources)
    : config_(config), pipeline_(pipeline) {
  BlackBoxRingOptions options;
  options.span = std::chrono::milliseconds(static_cast<int64_t>(config.minutes * 60000));
  options.max_bytes = config.max_bytes / std::max<size_t>(1, sources.size());
  for (const auto& source : sources) {
    auto r = std::make_unique<Recorder>();
    r->source = source;
    r->ring = std::make_unique<BlackBoxRing>(fs::path(config.folder) / "ring" / source, source, options,
                                             [source](const std::string& line) { log("'" + source + "': " + line); });
    if (r->ring->frame_sets() > 0) {
      const double age_s =
          std::chrono::duration<double>(std::chrono::system_clock::now() - r->ring->segments().back().last).count();
      log("'" + source + "': kept " + describe_span(r->ring->span().count()) + " from before the restart (its newest " +
          describe_span(std::max(0.0, age_s)) + " ago; it goes as new frame sets come)");
    }
    recorders_.push_back(std::move(r));
  }
  // A ring the last run did not close (its marker is still there): the daemon crashed or
  // the power went. Its minutes are saved before new frame sets push them out.
  for (auto& r : recorders_) {
    const fs::path marker = r->ring->folder() / kOpenMarker;
    std::error_code ec;
    const bool unclean = fs::exists(marker, ec);
    std::ofstream(marker) << "omniviewd keeps this black box; a clean stop removes this file\n";
    if (!unclean || r->ring->frame_sets() == 0) continue;
    try {
      for (const auto& s : save_locked(r->source + "-crash-" + utc_stamp(), {r.get()})) {
        log("'" + r->source + "': the last run stopped without closing its black box (a crash, a power cut): saved its " +
            describe_span(s.span.count()) + " to " + s.folder.string());
      }
    } catch (const std::exception& e) {
      log("'" + r->source + "': the last run stopped without closing its black box; it could not be saved: " + e.what());
    }
  }
  // Every tap first: a failure leaves no thread running (this constructor throws, and no
  // destructor joins them).
  try {
    for (auto& r : recorders_) r->tap = pipeline_.tap(r->source, /*passive=*/true, kQueue);
  } catch (...) {
    for (auto& r : recorders_) r->tap.reset();
    throw;
  }
  for (auto& r : recorders_) r->writer = std::thread([this, rec = r.get()] { write_loop(*rec); });
  watcher_ = std::thread([this] { watch_loop(); });
}

BlackBox::~BlackBox() { stop(); }

void BlackBox::stop() {
  if (stopping_.exchange(true)) return;
  {
    std::lock_guard lock(watch_mutex_);
  }
  watch_wake_.notify_all();
  if (watcher_.joinable()) watcher_.join();
  for (auto& r : recorders_) {
    if (r->tap) r->tap->close("the black box stops");  // the writer's take() returns at once
    if (r->writer.joinable()) r->writer.join();
    r->tap.reset();  // leaves the source
    std::lock_guard lock(r->mutex);
    try {
      r->ring->seal();
      std::error_code ec;
      fs::remove(r->ring->folder() / kOpenMarker, ec);  // closed cleanly
    } catch (const std::exception& e) {
      log("'" + r->source + "': " + e.what());
    }
  }
}

void BlackBox::write_loop(Recorder& r) {
  while (!stopping_) {
    const auto taken = r.tap->take(std::chrono::milliseconds(200));
    if (!taken) continue;
    if (!taken->frames) return;  // closed
    std::lock_guard lock(r.mutex);
    try {
      if (!r.ring->write(*taken->frames)) {
        ++r.not_kept;
        r.message = "a frame set larger than a segment (an eighth of the source's share of max_bytes) was not kept";
      } else {
        r.message.clear();  // writing again (the count of what was not kept stays)
      }
    } catch (const std::exception& e) {
      ++r.not_kept;
      r.message = e.what();
      if (Clock::now() - r.last_error_log > kErrorLogInterval) {
        r.last_error_log = Clock::now();
        log("'" + r.source + "': not kept: " + r.message + " (" + std::to_string(r.not_kept) + " frame sets so far)");
      }
    }
  }
}

// A source whose connection drops (a robot out of Wi-Fi reach, a camera unplugged): its
// ring saved as it is, the minutes before the drop. At most once per half span per
// source, so a flapping link cannot fill the disk with copies of the same minutes.
void BlackBox::watch_loop() {
  std::unique_lock lock(watch_mutex_);
  while (!watch_wake_.wait_for(lock, kWatchInterval, [&] { return stopping_.load(); })) {
    lock.unlock();
    for (auto& r : recorders_) {
      bool connected = false;
      try {
        connected = pipeline_.source_health(r->source).connected;
      } catch (const std::exception&) {
        continue;
      }
      const bool dropped = r->was_connected && !connected;
      r->was_connected = connected;
      if (!dropped) continue;
      const auto min_gap = std::max(std::chrono::milliseconds(10000),
                                    std::chrono::milliseconds(static_cast<int64_t>(config_.minutes * 30000)));
      {
        std::lock_guard rl(r->mutex);
        if (r->ring->frame_sets() == 0) continue;
        if (r->last_auto_save != Clock::time_point{} && Clock::now() - r->last_auto_save < min_gap) {
          log("'" + r->source + "' lost again: not saved again so soon (" + r->last_snapshot + " has the minutes before)");
          continue;
        }
        r->last_auto_save = Clock::now();
      }
      const std::string name = r->source + "-lost-" + utc_stamp();
      try {
        std::lock_guard save(save_mutex_);
        for (const auto& s : save_locked(name, {r.get()})) {
          log("'" + r->source + "' lost its connection: saved the " + describe_span(s.span.count()) + " before it to " +
              s.folder.string() + (s.note.empty() ? "" : " (" + s.note + ")"));
        }
      } catch (const std::exception& e) {
        log("'" + r->source + "' lost its connection; its ring could not be saved: " + e.what());
      }
    }
    lock.lock();
  }
}

std::vector<SnapshotSummary> BlackBox::save(const std::string& name, const std::string& source) {
  static const std::regex kName("[A-Za-z0-9][A-Za-z0-9._-]{0,63}");
  if (!std::regex_match(name, kName)) {
    throw SnapshotError(SnapshotError::Kind::kInvalidName,
                        "snapshot name '" + name + "': use 1-64 letters, digits, '.', '_' or '-', starting with a letter or digit");
  }
  std::vector<Recorder*> chosen;
  for (auto& r : recorders_) {
    if (source.empty() || r->source == source) chosen.push_back(r.get());
  }
  if (chosen.empty()) {
    std::string names;
    for (auto& r : recorders_) names += (names.empty() ? "" : ", ") + r->source;
    throw SnapshotError(SnapshotError::Kind::kUnknownSource,
                        "no source '" + source + "' in the black box (it keeps: " + names + ")");
  }
  std::lock_guard lock(save_mutex_);
  auto saved = save_locked(name, chosen);
  for (const auto& s : saved) {
    log("'" + s.source + "': saved " + describe_span(s.span.count()) + " (" + std::to_string(s.frame_sets) +
        " frame sets) to " + s.folder.string() + " on request");
  }
  return saved;
}

std::vector<SnapshotSummary> BlackBox::save_locked(const std::string& name, const std::vector<Recorder*>& recorders) {
  const fs::path snapshots = fs::path(config_.folder) / "snapshots";
  const fs::path target = snapshots / name;
  std::error_code ec;
  if (fs::exists(target, ec)) {
    throw SnapshotError(SnapshotError::Kind::kExists, "a snapshot '" + name + "' exists already (" + target.string() + ")");
  }
  const bool per_source = recorders_.size() > 1;
  // Written under a hidden name and renamed when complete: a crash mid-save leaves no
  // half snapshot under the real name.
  const fs::path partial = snapshots / (".partial-" + name);
  const fs::path staging = snapshots / (".staging-" + name);
  fs::remove_all(partial, ec);
  fs::remove_all(staging, ec);
  std::vector<SnapshotSummary> saved;
  try {
    for (Recorder* r : recorders) {
      std::vector<fs::path> staged;
      {
        std::lock_guard lock(r->mutex);
        r->ring->seal();  // what the ring holds, complete on disk
        staged = r->ring->stage(staging / r->source);
      }
      if (staged.empty()) continue;
      const fs::path out = per_source ? partial / r->source : partial;
      fs::create_directories(out.parent_path());
      SnapshotSummary summary = merge_segments(staged, out, r->source);
      summary.folder = per_source ? target / r->source : target;
      saved.push_back(std::move(summary));
    }
    fs::remove_all(staging, ec);
    if (saved.empty()) {
      throw SnapshotError(SnapshotError::Kind::kEmpty,
                          "the black box holds nothing yet: it keeps what the sources deliver, and a source delivers "
                          "only while someone watches one of its views");
    }
    fs::create_directories(snapshots);
    fs::rename(partial, target);
  } catch (const SnapshotError&) {
    fs::remove_all(partial, ec);
    fs::remove_all(staging, ec);
    throw;
  } catch (const std::exception& e) {
    fs::remove_all(partial, ec);
    fs::remove_all(staging, ec);
    throw SnapshotError(SnapshotError::Kind::kFailed, "snapshot '" + name + "' not saved: " + e.what());
  }
  for (Recorder* r : recorders) {
    std::lock_guard lock(r->mutex);
    r->last_snapshot = (per_source ? target / r->source : target).string();
  }
  return saved;
}

std::vector<BlackBoxRingReport> BlackBox::report() const {
  std::vector<BlackBoxRingReport> rings;
  for (const auto& r : recorders_) {
    BlackBoxRingReport& out = rings.emplace_back();
    out.source = r->source;
    std::lock_guard lock(r->mutex);
    out.folder = r->ring->folder().string();
    out.span_s = r->ring->span().count();
    out.bytes = r->ring->bytes();
    out.max_bytes = config_.max_bytes / recorders_.size();
    out.minutes = config_.minutes;
    out.frame_sets = r->ring->frame_sets();
    out.not_kept = r->not_kept + (r->tap ? r->tap->skipped() : 0);
    out.message = r->message;
    out.last_snapshot = r->last_snapshot;
  }
  return rings;
}

}  // namespace omniview
