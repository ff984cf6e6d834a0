// Built and run in the ThreadSanitizer tree only (tests/map/CMakeLists.txt): a thread writes
// a camera image while apply_map reads it, with nothing ordering the two. apply_map's pixel
// rows run there without ThreadSanitizer's per-access checks (core/CMakeLists.txt says why),
// so this race is reported only if apply_map declares the image it reads: CTest expects
// the report, naming apply_map.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>

#include "core/map/apply.h"

int main() {
  using omniview::MapEntry;
  constexpr int kSide = 64;
  omniview::FusionMap map;
  map.width = map.height = kSide;
  map.camera_sizes = {cv::Size(kSide, kSide)};
  map.camera_names = {"probe"};
  map.camera_used = {true};
  map.primary.resize(kSide * kSide);
  for (int i = 0; i < kSide * kSide; ++i) {
    const int row = std::min(i / kSide, kSide - 2), col = std::min(i % kSide, kSide - 2);
    map.primary[i] = MapEntry{static_cast<uint32_t>(row * kSide + col), 128, 128, 0, 0};
  }
  std::vector<cv::Mat> images = {cv::Mat(kSide, kSide, CV_8UC1, cv::Scalar(0))};
  // The camera's next picture, written into the image the frame is made from (the bug a
  // source without double buffering would have).
  // Relaxed: apply_map starts after the writes (so TSan reports apply_map's read, the
  // regex's order) with no happens-before edge between them.
  std::atomic<bool> written{false};
  std::thread writer([&] {
    for (int i = 0; i < kSide * kSide; ++i) images[0].data[i] = static_cast<uint8_t>(i);
    written.store(true, std::memory_order_relaxed);
  });
  while (!written.load(std::memory_order_relaxed)) std::this_thread::yield();
  cv::Mat out;
  omniview::apply_map(map, images, out, 1);
  writer.join();
  std::printf("applied %dx%d with no report\n", out.cols, out.rows);
  return 0;
}
