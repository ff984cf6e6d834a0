#include "core/map/apply.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/map/apply_avx2.h"
#include "core/map/apply_rows.h"
#include "core/map/thread_sanitizer.h"

namespace omniview {
namespace {

using apply_internal::Source;

#ifdef OMNIVIEW_APPLY_AVX2
// The AVX2 rows address every camera from one base pointer with 32-bit offsets: true if
// the used images lie close enough together (they do when the allocator maps them near
// each other, as glibc does; otherwise the portable rows run).
bool make_gather_sources(const std::vector<Source>& sources, apply_internal::GatherSources& g) {
  if (sources.size() > 8) return false;
  uintptr_t lo = UINTPTR_MAX, hi = 0;
  for (size_t i = 0; i < sources.size(); ++i) {
    if (sources[i].data == nullptr) continue;
    const auto start = reinterpret_cast<uintptr_t>(sources[i].data);
    lo = std::min(lo, start);
    hi = std::max(hi, start + sources[i].stride * static_cast<size_t>(sources[i].rows));
  }
  if (hi == 0 || hi - lo >= (uintptr_t{1} << 31)) return false;
  g.base = reinterpret_cast<const uint8_t*>(lo);
  for (size_t i = 0; i < sources.size(); ++i) {
    if (sources[i].data == nullptr) continue;
    g.delta[i] = static_cast<int32_t>(reinterpret_cast<uintptr_t>(sources[i].data) - lo);
    g.stride[i] = static_cast<int32_t>(sources[i].stride);
    g.last_wide[i] = g.delta[i] + static_cast<int32_t>(sources[i].stride * sources[i].rows) - 8;
  }
  return true;
}
#endif

std::atomic<bool> g_simd_enabled{true};

// The rows run without ThreadSanitizer's per-access checks (core/CMakeLists.txt): what
// they read and write is declared here, on the calling thread, which the pool's workers
// start after and finish before. A thread that writes a camera image or the output (or
// frees it) while a frame is applied is reported as before; only a race between two of
// this call's own workers is not, and cv::parallel_for_ gives each row to one worker.
void declare_to_thread_sanitizer(const FusionMap& map, const std::vector<Source>& sources, cv::Mat& out) {
  if (!thread_sanitizer::active) return;
  for (const Source& s : sources) {
    if (s.data != nullptr) thread_sanitizer::reads(s.data, s.stride * static_cast<size_t>(s.rows));
  }
  thread_sanitizer::reads(map.primary.data(), map.primary.size() * sizeof(MapEntry));
  thread_sanitizer::reads(map.secondary.data(), map.secondary.size() * sizeof(MapEntry));
  thread_sanitizer::reads(map.primary_weight.data(),
                          map.primary_weight.size() * sizeof(map.primary_weight[0]));
  for (int row = 0; row < out.rows; ++row) thread_sanitizer::writes(out.ptr(row), out.cols * out.elemSize());
}

}  // namespace

namespace apply_internal {
void set_simd_enabled(bool enabled) { g_simd_enabled = enabled; }
bool simd_enabled() { return g_simd_enabled; }
}  // namespace apply_internal

void apply_map(const FusionMap& map, const std::vector<cv::Mat>& images, cv::Mat& out, int out_channels) {
  apply_map(map, images, out, out_channels, CameraGains{});
}

void apply_map(const FusionMap& map, const std::vector<cv::Mat>& images, cv::Mat& out, int out_channels,
               const CameraGains& gains) {
  if (out_channels != 1 && out_channels != 3) {
    throw std::invalid_argument("output must have 1 or 3 channels, not " + std::to_string(out_channels));
  }
  std::vector<uint8_t> lut;
  if (!gains.empty()) {
    if (gains.channels != out_channels || gains.cameras() != map.camera_sizes.size() ||
        gains.gain.size() != gains.cameras() * static_cast<size_t>(out_channels)) {
      throw std::invalid_argument("gains are for " + std::to_string(gains.cameras()) + " camera(s) and " +
                                  std::to_string(gains.channels) + " channel(s), the view has " +
                                  std::to_string(map.camera_sizes.size()) + " and " + std::to_string(out_channels));
    }
    lut.resize(gains.gain.size() * 256);
    for (size_t t = 0; t < gains.gain.size(); ++t) {
      const float g = std::isfinite(gains.gain[t]) ? std::max(gains.gain[t], 0.0f) : 1.0f;
      for (int v = 0; v < 256; ++v) lut[t * 256 + v] = cv::saturate_cast<uint8_t>(g * static_cast<float>(v));
    }
  }
  if (images.size() != map.camera_sizes.size()) {
    throw std::invalid_argument("expected " + std::to_string(map.camera_sizes.size()) + " images (one per camera), got " +
                                std::to_string(images.size()));
  }
  // Camera i at pyramid level l is source i + l * cameras (footprint.h).
  const size_t cameras = images.size();
  int levels = 0;
  for (size_t i = 0; i < map.camera_levels.size(); ++i) levels = std::max<int>(levels, map.camera_levels[i]);
  std::vector<Source> sources(cameras * (levels + 1));
  std::vector<cv::Mat> continuous(sources.size());
  bool uniform = map.secondary.empty() && lut.empty();  // the fast rows know no gains
  for (size_t i = 0; i < images.size(); ++i) {
    if (!map.camera_used[i]) continue;
    const cv::Mat& img = images[i];
    const std::string who = "camera '" + map.camera_names[i] + "'";
    if (img.empty()) throw std::invalid_argument(who + ": no image, but the view needs this camera");
    if (img.type() != CV_8UC1 && img.type() != CV_8UC3) {
      throw std::invalid_argument(who + ": image must be 8-bit greyscale or BGR, got " + std::to_string(img.channels()) +
                                  " channel(s) of depth " + std::to_string(img.depth()));
    }
    if (img.size() != map.camera_sizes[i]) {
      throw std::invalid_argument(who + ": image is " + std::to_string(img.cols) + "x" + std::to_string(img.rows) +
                                  " but the calibration is for " + std::to_string(map.camera_sizes[i].width) + "x" +
                                  std::to_string(map.camera_sizes[i].height));
    }
    continuous[i] = img.isContinuous() ? img : img.clone();  // map offsets assume packed rows
    uniform = uniform && img.channels() == out_channels;
  }
  // The pyramid levels this map reads, built once per frame (each camera in parallel).
  cv::parallel_for_(cv::Range(0, static_cast<int>(cameras)), [&](const cv::Range& r) {
    for (int i = r.start; i < r.end; ++i) {
      const int deepest = map.camera_levels.empty() || !map.camera_used[i] ? 0 : map.camera_levels[i];
      for (int l = 1; l <= deepest; ++l) cv::pyrDown(continuous[i + (l - 1) * cameras], continuous[i + l * cameras]);
    }
  });
  for (size_t i = 0; i < sources.size(); ++i) {
    const cv::Mat& img = continuous[i];
    if (img.empty()) continue;
    sources[i] = Source{img.data, img.step[0], img.channels(), img.rows,
                        static_cast<uint32_t>((img.rows - 2) * img.cols + img.cols - 2)};
  }
  out.create(map.height, map.width, out_channels == 3 ? CV_8UC3 : CV_8UC1);
  const int w = map.width;
  declare_to_thread_sanitizer(map, sources, out);
#ifdef OMNIVIEW_APPLY_AVX2
  static const bool avx2 = apply_internal::have_avx2();
  apply_internal::GatherSources gather;
  const bool use_avx2 = avx2 && apply_internal::simd_enabled() && uniform && make_gather_sources(sources, gather);
#else
  const bool use_avx2 = false;
#endif
  // A few stripes per thread: large enough that neighbours share no output cache line in
  // the middle of their work, small enough to even out a loaded core.
  const int stripes = std::min(map.height, 8 * std::max(1, cv::getNumThreads()));
  cv::parallel_for_(cv::Range(0, map.height), [&](const cv::Range& rows) {
    for (int row = rows.start; row < rows.end; ++row) {
      const size_t first = static_cast<size_t>(row) * w;
      uint8_t* dst = out.ptr<uint8_t>(row);
#ifdef OMNIVIEW_APPLY_AVX2
      if (use_avx2) {
        if (out_channels == 3) {
          apply_internal::apply_row_bgr_avx2(&map.primary[first], w, gather, static_cast<int>(cameras), dst);
        } else {
          apply_internal::apply_row_grey_avx2(&map.primary[first], w, gather, static_cast<int>(cameras), dst);
        }
        continue;
      }
#endif
      if (uniform && out_channels == 3) {
        apply_internal::apply_row_uniform_bgr(&map.primary[first], sources.data(), static_cast<int>(cameras), w, dst);
      } else if (uniform) {
        apply_internal::apply_row_uniform_grey(&map.primary[first], sources.data(), static_cast<int>(cameras), w, dst);
      } else {
        apply_internal::apply_row_general(map, first, sources.data(), lut.empty() ? nullptr : lut.data(), w, out_channels, dst);
      }
    }
  }, stripes);
}

}  // namespace omniview
