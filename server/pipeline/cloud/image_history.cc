#include "server/pipeline/cloud/image_history.h"

#include <algorithm>
#include <cmath>

namespace omniview {

void ImageHistory::add(const FrameSet& frames) {
  if (!frames.rig || frames.images.size() < frames.rig->cameras().size()) return;
  if (std::any_of(frames.images.begin(), frames.images.end(), [](const cv::Mat& m) { return m.empty(); })) return;
  FrameSet kept = frames;
  kept.cloud.reset();  // the history is for images; clouds come one at a time
  kept.encoded.clear();
  sets_.push_back(std::move(kept));
  while (sets_.size() > max_sets || sets_.front().capture_time + max_age < sets_.back().capture_time) {
    sets_.pop_front();
  }
}

const FrameSet* ImageHistory::nearest(std::chrono::system_clock::time_point t,
                                      const std::shared_ptr<const Rig>& rig) const {
  const FrameSet* best = nullptr;
  for (const FrameSet& s : sets_) {
    if (s.rig != rig) continue;  // images of another calibration
    const auto gap = s.capture_time > t ? s.capture_time - t : t - s.capture_time;
    const auto best_gap = best ? (best->capture_time > t ? best->capture_time - t : t - best->capture_time) : gap;
    if (!best || gap <= best_gap) best = &s;  // ties: the newer
  }
  return best;
}

std::chrono::system_clock::time_point cloud_mid_time(const PointCloud& cloud) {
  if (cloud.time.empty()) return cloud.stamp;
  const auto [lo, hi] = std::minmax_element(cloud.time.begin(), cloud.time.end());
  const double mid_s = 0.5 * (double(*lo) + double(*hi));
  if (!std::isfinite(mid_s)) return cloud.stamp;
  return cloud.stamp +
         std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::duration<double>(mid_s));
}

}  // namespace omniview
