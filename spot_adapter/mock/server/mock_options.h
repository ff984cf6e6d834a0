// spot-mock's command line (serving; the `control` subcommand has its own, see
// control/control_command.h).
#pragma once

#include <chrono>

#include <optional>
#include <string>
#include <vector>

#include "spot_adapter/mock/services/mock_robot.h"

namespace omniview::spot_mock {

struct MockOptions {
  std::string bind = "127.0.0.1";
  int port = 50443;  // 0: any free port (see ready_file)
  // Where config/spot.yaml looks, from the repository root.
  std::string certs_dir = "out/spot-mock";
  std::string credentials_file = "out/spot-mock/credentials.yaml";
  std::string ready_file;
  std::chrono::milliseconds clock_offset{0};  // the robot's clock minus this machine's
  MockRobotConfig robot;  // scene, colour, faults, token policy (credentials come from the file)
};

struct ParsedOptions {
  std::optional<MockOptions> options;  // nullopt: exit with `exit_code` (help printed, or an error)
  int exit_code = 0;
};

// Parses the arguments after the program name; prints --help, or an error naming the flag
// (never a flag's value).
ParsedOptions parse_mock_options(const std::vector<std::string>& args);

void print_mock_help();

// Small helpers the control subcommand shares: a number or a flag's value, or an error naming `flag`.
double parse_double(const std::string& flag, const std::string& text);
int parse_int(const std::string& flag, const std::string& text, int min, int max);

}  // namespace omniview::spot_mock
