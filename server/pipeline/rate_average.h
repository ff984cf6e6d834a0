// Frame rates from arrival intervals, for status.
#pragma once

namespace omniview {

// Folds interval `dt_s` into the exponential average `mean_interval_s` (weight of the new
// one: `weight`) and returns the rate it stands for. Averaging the intervals, not the
// rates 1/dt: the mean of 1/dt exceeds 1/(mean dt) whenever intervals jitter, so averaged
// rates showed a view faster than the source that feeds it.
inline double add_interval(double& mean_interval_s, double dt_s, double weight) {
  if (!(dt_s > 0)) return mean_interval_s > 0 ? 1 / mean_interval_s : 0;
  mean_interval_s = mean_interval_s == 0 ? dt_s : (1 - weight) * mean_interval_s + weight * dt_s;
  return 1 / mean_interval_s;
}

}  // namespace omniview
