// Gain estimation from one image set: the mean intensity each camera shows in its overlap
// with each other camera (over the map's overlap samples), then Brown & Lowe's least-squares
// gains with a prior pulling every gain toward 1.
#pragma once

#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/gain/camera_gains.h"
#include "core/map/fusion_map.h"

namespace omniview {

// Per output channel, per ordered camera pair (i, j): how many samples the two share, the
// sum of camera i's values over them (sum(i, j) != sum(j, i): each camera's own view), and
// for i < j every sample's log(value_i / value_j).
//
// Why the log ratios: where the scene lies off the view's surface (a floor under a view's
// plane) the two cameras show different things at the same view pixel, and the mean of
// what each shows there can differ by more than the exposures do (measured: 5-7 % off on
// Spot's floor). The median of the per-sample log ratios is not moved by that: registered
// samples (the scene on the surface) all sit at the true ratio, and misregistered ones
// spread around it.
struct OverlapStats {
  int cameras = 0, channels = 0;
  std::vector<double> count;  // [channel][i][j], symmetric
  std::vector<double> sum;    // [channel][i][j]: camera i's values where it overlaps j
  std::vector<std::vector<float>> log_ratio;  // [channel][i][j], filled for i < j

  size_t index(int channel, int i, int j) const {
    return (static_cast<size_t>(channel) * cameras + i) * cameras + j;
  }
};

// Samples both cameras at map.gain_samples, in `channels` output channels (1: luma, as
// apply_map delivers it; 3: BGR, grey cameras giving their grey in each). Samples dark or
// saturated in either camera (below 8 or above 247) are left out: there a gain does not
// describe the difference. images as for apply_map; throws std::invalid_argument naming
// the camera for a missing or wrong-size image.
OverlapStats measure_overlaps(const FusionMap& map, const std::vector<cv::Mat>& images, int channels);

struct GainPrior {
  // Brown & Lowe's error: over each overlapping pair {i, j}, N_ij (g_i I_ij - g_j I_ji)^2 /
  // sigma_n^2, plus over each camera i and its overlaps, N_ij (1 - g_i)^2 / sigma_g^2. They use sigma_g = 0.1; with intensities near mid-grey that
  // prior keeps a third of a 0.7 : 1.3 exposure step, so it is looser here: strong enough
  // to hold the overall brightness and to keep a camera with little overlap near 1.
  double sigma_noise = 10;  // grey levels
  double sigma_gain = 0.5;
  double min_gain = 0.25, max_gain = 4;  // a clamp against a pathological scene
};

// The gains minimising that error, per channel; cameras without overlap get 1. `stats`
// with no samples at all gives all ones. I_ij / I_ji is the median ratio of the pair's
// samples where log_ratio holds them (else the ratio of the means), scaled to the pair's
// (geometric) mean intensity.
CameraGains solve_gains(const OverlapStats& stats, const GainPrior& prior = {});

}  // namespace omniview
