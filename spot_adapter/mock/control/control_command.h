// `spot-mock control ...`: drives a running mock's SpotMockControl service from a shell
// (tests and demos set faults, expire tokens, move joints and read counters with it).
#pragma once

#include <string>
#include <vector>

namespace omniview::spot_mock {

// `args` are the arguments after "control". Returns the exit code: 0 done, 1 the mock
// could not be reached or refused, 2 a usage error.
int run_control_command(const std::vector<std::string>& args);

}  // namespace omniview::spot_mock
