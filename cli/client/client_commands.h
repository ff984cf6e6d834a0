// The commands that talk to omniviewd, one file each. Each takes the arguments after its
// name and returns the exit status; usage errors throw UsageError, failed calls RpcError.
#pragma once

#include <string>
#include <vector>

namespace omniview::cli {

int cameras_command(const std::vector<std::string>& args);
int views_command(const std::vector<std::string>& args);
int ptz_command(const std::vector<std::string>& args);
int snapshot_command(const std::vector<std::string>& args);
int watch_command(const std::vector<std::string>& args);
int stream_command(const std::vector<std::string>& args);
int status_command(const std::vector<std::string>& args);
int record_command(const std::vector<std::string>& args);
int joints_command(const std::vector<std::string>& args);
int blackbox_command(const std::vector<std::string>& args);
int show_command(const std::vector<std::string>& args);
int cloud_command(const std::vector<std::string>& args);

}  // namespace omniview::cli
