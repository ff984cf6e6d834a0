#include "core/gain/gain_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Dense>

namespace omniview {
namespace {

constexpr int kDark = 8, kBright = 247;

// One camera's value at a map entry, in `channels` output channels. Entries on a pyramid
// level (footprint.h) are read as the full-size pixel nearest the same point: a mean over
// thousands of samples needs no pre-filtering, and the pyramid is apply_map's, not ours.
void sample(const cv::Mat& img, const MapEntry& e, cv::Size level0, int channels, uint8_t* out) {
  int w = level0.width;
  for (int l = 0; l < e.level; ++l) w = (w + 1) / 2;  // cv::pyrDown's sizes
  const int x = static_cast<int>(e.offset % static_cast<uint32_t>(w)), y = static_cast<int>(e.offset / w);
  const int scale = 1 << e.level;
  const int u = std::min(level0.width - 1, ((x << 8) + e.fx + 128) * scale >> 8);
  const int v = std::min(level0.height - 1, ((y << 8) + e.fy + 128) * scale >> 8);
  const uint8_t* p = img.ptr<uint8_t>(v) + static_cast<size_t>(u) * img.channels();
  if (img.channels() == 1) {
    std::fill(out, out + channels, p[0]);
  } else if (channels == 3) {
    std::copy(p, p + 3, out);
  } else {  // luma with BT.601 weights in 1/256, as apply_map computes it
    out[0] = static_cast<uint8_t>((29 * p[0] + 150 * p[1] + 77 * p[2] + 128) >> 8);
  }
}

// Camera i's and camera j's mean intensity over their overlap, as the least squares use
// them: their geometric mean, split by the median ratio (see OverlapStats).
std::pair<double, double> pair_intensities(const OverlapStats& s, int c, int i, int j) {
  const double n = s.count[s.index(c, i, j)];
  const double mean_i = s.sum[s.index(c, i, j)] / n, mean_j = s.sum[s.index(c, j, i)] / n;
  const bool forward = i < j;
  static const std::vector<float> kNone;
  const auto& ratios = s.log_ratio.empty() ? kNone : s.log_ratio[forward ? s.index(c, i, j) : s.index(c, j, i)];
  if (ratios.empty()) return {mean_i, mean_j};
  std::vector<float> sorted = ratios;
  const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  const double log_ratio = forward ? *middle : -*middle;  // log(I_i / I_j)
  const double m = std::sqrt(mean_i * mean_j);
  return {m * std::exp(log_ratio / 2), m * std::exp(-log_ratio / 2)};
}

}  // namespace

OverlapStats measure_overlaps(const FusionMap& map, const std::vector<cv::Mat>& images, int channels) {
  if (channels != 1 && channels != 3) {
    throw std::invalid_argument("gain estimation: 1 or 3 channels, not " + std::to_string(channels));
  }
  if (images.size() != map.camera_sizes.size()) {
    throw std::invalid_argument("gain estimation: expected " + std::to_string(map.camera_sizes.size()) +
                                " images (one per camera), got " + std::to_string(images.size()));
  }
  for (size_t i = 0; i < images.size(); ++i) {
    if (i >= map.camera_used.size() || !map.camera_used[i]) continue;
    const cv::Mat& img = images[i];
    if (img.empty() || (img.type() != CV_8UC1 && img.type() != CV_8UC3) || img.size() != map.camera_sizes[i]) {
      throw std::invalid_argument("gain estimation: camera '" + map.camera_names[i] +
                                  "' has no 8-bit image of its calibrated size");
    }
  }
  OverlapStats s;
  s.cameras = static_cast<int>(map.camera_sizes.size());
  s.channels = channels;
  const size_t n = static_cast<size_t>(channels) * s.cameras * s.cameras;
  s.count.assign(n, 0);
  s.sum.assign(n, 0);
  s.log_ratio.assign(n, {});
  for (const uint32_t i : map.gain_samples) {
    const MapEntry& a = map.primary[i];
    const MapEntry& b = map.secondary[i];
    uint8_t va[3], vb[3];
    sample(images[a.cam], a, map.camera_sizes[a.cam], channels, va);
    sample(images[b.cam], b, map.camera_sizes[b.cam], channels, vb);
    for (int c = 0; c < channels; ++c) {
      if (va[c] < kDark || vb[c] < kDark || va[c] > kBright || vb[c] > kBright) continue;
      s.count[s.index(c, a.cam, b.cam)] += 1;
      s.count[s.index(c, b.cam, a.cam)] += 1;
      s.sum[s.index(c, a.cam, b.cam)] += va[c];
      s.sum[s.index(c, b.cam, a.cam)] += vb[c];
      // A table of log(v) would be faster; a few thousand logs per frame do not show.
      const float r = std::log(static_cast<float>(va[c]) / static_cast<float>(vb[c]));
      if (a.cam < b.cam) {
        s.log_ratio[s.index(c, a.cam, b.cam)].push_back(r);
      } else {
        s.log_ratio[s.index(c, b.cam, a.cam)].push_back(-r);
      }
    }
  }
  return s;
}

CameraGains solve_gains(const OverlapStats& stats, const GainPrior& prior) {
  const int n = stats.cameras;
  CameraGains gains;
  gains.channels = stats.channels;
  gains.gain.assign(static_cast<size_t>(n) * stats.channels, 1.0f);
  const double wn = 1 / (prior.sigma_noise * prior.sigma_noise), wg = 1 / (prior.sigma_gain * prior.sigma_gain);
  for (int c = 0; c < stats.channels; ++c) {
    // Normal equations of the error above (gain_estimate.h), each unordered pair once.
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const double N = stats.count[stats.index(c, i, j)];
        if (N <= 0) continue;
        const auto [Iij, Iji] = pair_intensities(stats, c, i, j);
        // d/dg_i of N (g_i Iij - g_j Iji)^2 wn + N (1 - g_i)^2 wg (the pair (j, i) adds
        // the same terms for g_j).
        A(i, i) += N * (Iij * Iij * wn + wg);
        A(i, j) -= N * Iij * Iji * wn;
        b(i) += N * wg;
      }
    }
    for (int i = 0; i < n; ++i) {
      if (A(i, i) == 0) A(i, i) = 1, b(i) = 1;  // no overlap: nothing to correct
    }
    const Eigen::VectorXd g = A.ldlt().solve(b);
    for (int i = 0; i < n; ++i) {
      const double gi = std::isfinite(g(i)) ? std::clamp(g(i), prior.min_gain, prior.max_gain) : 1.0;
      gains.gain[static_cast<size_t>(i) * stats.channels + c] = static_cast<float>(gi);
    }
  }
  return gains;
}

}  // namespace omniview
