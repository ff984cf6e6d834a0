// The last few complete image sets of a source, so a cloud is coloured with the set taken
// nearest its own time rather than with whichever set it happened to arrive with (a cloud
// that completes just after an image set belongs with that set, not the next one).
#pragma once

#include <chrono>
#include <deque>

#include "server/source/frame_set.h"

namespace omniview {

class ImageHistory {
 public:
  // Keeps `frames` if every camera has an image (a cloud needs them all); older sets beyond
  // `max_sets` or `max_age` before the newest are forgotten.
  void add(const FrameSet& frames);
  // The kept set of `rig` whose capture time is nearest `t`; null when none.
  const FrameSet* nearest(std::chrono::system_clock::time_point t, const std::shared_ptr<const Rig>& rig) const;
  void clear() { sets_.clear(); }

  static constexpr size_t max_sets = 4;
  static constexpr std::chrono::milliseconds max_age{500};

 private:
  std::deque<FrameSet> sets_;  // copies share the pixels
};

// When the cloud's points were measured, as one time: the middle of its sweep when it has
// per-point times, else its stamp.
std::chrono::system_clock::time_point cloud_mid_time(const PointCloud& cloud);

}  // namespace omniview
