#include "spot_adapter/mock/state/faults.h"

#include <random>

namespace omniview::spot_mock {

bool chance(double p) {
  if (p <= 0) return false;
  if (p >= 1) return true;
  thread_local std::mt19937_64 engine{std::random_device{}()};  // one per gRPC thread: no lock
  return std::uniform_real_distribution<double>(0, 1)(engine) < p;
}

}  // namespace omniview::spot_mock
