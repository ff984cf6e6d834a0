// The black box (config `blackbox:`): the daemon keeps the last minutes of what each source
// delivers (camera images as received, clouds, joints, rig) in a ring on disk
// (black_box_ring.h), and saves it as an ordinary recording (replayable, exportable to
// MCAP) when asked (`omniview blackbox save NAME`, SaveBlackBox) or by itself when a
// source's connection drops: the minutes before the drop.
//
// It records what flows: a passive tap (pipeline.h) asks a source for nothing, so a robot
// nobody watches is not pulled for the black box's sake, and it costs a file write per
// image. Folder layout:
//   <folder>/ring/<source>/<segment>/   the ring (max_bytes shared equally by the sources)
//   <folder>/snapshots/<name>/          a snapshot of a one-source daemon: a recording
//   <folder>/snapshots/<name>/<source>/ the same, per source, with several
// Snapshots are outside the ring's budget: they stay until someone removes them.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "server/blackbox/black_box_ring.h"
#include "server/blackbox/snapshot_merge.h"
#include "server/config/daemon_config.h"
#include "server/pipeline/pipeline.h"

namespace omniview {

// Why a snapshot was not saved; the API maps each kind to its status code.
class SnapshotError : public std::runtime_error {
 public:
  enum class Kind { kInvalidName, kExists, kUnknownSource, kEmpty, kFailed };
  SnapshotError(Kind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  Kind kind() const { return kind_; }

 private:
  Kind kind_;
};

// One source's ring, for GetStatus.
struct BlackBoxRingReport {
  std::string source, folder;
  double span_s = 0;  // newest kept frame set's capture time minus the oldest's
  uint64_t bytes = 0, max_bytes = 0;  // on disk now; this source's share of the budget
  double minutes = 0;
  uint64_t frame_sets = 0, not_kept = 0;
  std::string message;        // the last problem; empty while writing works
  std::string last_snapshot;  // empty before any
};

class BlackBox {
 public:
  // Opens (or creates) each source's ring under config.folder, keeping what an earlier run
  // left there, and starts keeping what the sources deliver. Throws std::runtime_error
  // naming the folder when it cannot be created or written.
  BlackBox(const BlackBoxConfig& config, Pipeline& pipeline, const std::vector<std::string>& sources);
  ~BlackBox();
  BlackBox(const BlackBox&) = delete;
  BlackBox& operator=(const BlackBox&) = delete;

  // Stops keeping frames and closes the segments being written. Idempotent.
  void stop();

  // Saves the ring of `source` (empty: every source) as snapshots/<name>. Throws
  // SnapshotError: a name that is not 1-64 of [A-Za-z0-9._-] (starting with a letter or
  // digit), one already saved, an unknown source, nothing kept yet, or a write failure.
  std::vector<SnapshotSummary> save(const std::string& name, const std::string& source = "");

  // Each source's ring, for GetStatus.
  std::vector<BlackBoxRingReport> report() const;

  // Whether `folder` can hold a black box (created if missing): for `omniviewd --check`,
  // which must not touch a ring. Throws std::runtime_error naming it.
  static void check_folder(const std::string& folder);

 private:
  struct Recorder;

  void write_loop(Recorder& recorder);
  void watch_loop();
  std::vector<SnapshotSummary> save_locked(const std::string& name, const std::vector<Recorder*>& recorders);

  const BlackBoxConfig config_;
  Pipeline& pipeline_;
  std::vector<std::unique_ptr<Recorder>> recorders_;
  std::mutex save_mutex_;  // one snapshot at a time
  std::atomic<bool> stopping_{false};
  std::mutex watch_mutex_;
  std::condition_variable watch_wake_;
  std::thread watcher_;
};

}  // namespace omniview
