// omniview: the command-line tool. Subcommands live in their own files: `render` works
// offline, the others talk to the daemon omniviewd (cli/client/).
#include <algorithm>
#include <functional>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "cli/args.h"
#include "cli/client/client_commands.h"
#include "cli/client/connection.h"
#include "cli/colorize_command.h"
#include "cli/export_command.h"
#include "cli/render_command.h"
#include "core/io/yaml_reader.h"
#include "core/map/worker_threads.h"

namespace {

constexpr const char* kUsage = R"(usage: omniview COMMAND [options]
       omniview --version

commands:
  render    compute views offline from a rig and images (omniview render --help)
  colorize  colour a point cloud file offline from a rig and images (colorize --help)
  export    a recording as an MCAP file for Foxglove and Lichtblick (export --help)

talking to omniviewd:
  cameras   the cameras of the daemon's sources, with calibration and pose
  views     list, get, create, update, delete or save views (views --help)
  ptz       pan, tilt and zoom a view, absolutely or by steps
  snapshot  save the next frame of a view (-o out.png|.jpg|.raw, or - for stdout)
  watch     live frame rate, latency, size and drops of a view
  show      a live window of a view, with keyboard pan, tilt and zoom
  stream    save N frames of a view to a folder (or -o - : MJPEG to stdout)
  status    the daemon's sources, views and clients
  record    record what a source delivers, for the replay source
  joints    the robot overlay's joint positions: show them, or set them
  blackbox  save the daemon's black box (its last minutes) as a recording
  cloud     save a source's coloured lidar cloud (-o out.ply; --count N, --follow)

Connection options of those commands, before or after the command: --server HOST:PORT
(or OMNIVIEW_SERVER; default 127.0.0.1:50051), --tls-ca FILE, --tls-cert FILE --tls-key
FILE (a client certificate, where the daemon asks for one), --token-file FILE (or
OMNIVIEW_TOKEN, the token itself, or OMNIVIEW_TOKEN_FILE, a file holding it).

Run 'omniview COMMAND --help' for a command's options.
)";

using Command = std::function<int(const std::vector<std::string>&)>;

const std::map<std::string, Command>& commands() {
  namespace cli = omniview::cli;
  static const std::map<std::string, Command> table{
      {"render", cli::render_command}, {"cameras", cli::cameras_command},   {"views", cli::views_command},
      {"ptz", cli::ptz_command},       {"snapshot", cli::snapshot_command}, {"watch", cli::watch_command},
      {"stream", cli::stream_command}, {"status", cli::status_command},     {"record", cli::record_command},
      {"joints", cli::joints_command},  {"colorize", cli::colorize_command}, {"export", cli::export_command},
      {"show", cli::show_command},     {"cloud", cli::cloud_command},       {"blackbox", cli::blackbox_command}};
  return table;
}

// `omniview --server robot:50051 status` as well as `omniview status --server ...`: the
// connection options in front of the command move behind it. Throws UsageError for any
// other option there.
std::vector<std::string> command_first(const std::vector<std::string>& args) {
  const auto& connection = omniview::cli::connection_flags();
  std::vector<std::string> leading;
  size_t i = 0;
  for (; i < args.size() && args[i].rfind("--", 0) == 0; ++i) {
    const std::string name = args[i].substr(2, args[i].find('=') - 2);
    if (name == "help" || name == "version") break;
    if (std::find(connection.begin(), connection.end(), name) == connection.end()) {
      throw omniview::cli::UsageError("unknown option " + args[i] +
                                      " before the command (only connection options may come first; see --help)");
    }
    leading.push_back(args[i]);
    if (args[i].find('=') == std::string::npos) {
      if (i + 1 >= args.size()) throw omniview::cli::UsageError(args[i] + " needs a value");
      leading.push_back(args[++i]);
    }
  }
  if (leading.empty()) return args;
  if (i >= args.size()) throw omniview::cli::UsageError("missing COMMAND after the connection options (see --help)");
  std::vector<std::string> out{args[i]};
  out.insert(out.end(), args.begin() + static_cast<long>(i) + 1, args.end());
  out.insert(out.end(), leading.begin(), leading.end());
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    args = command_first(args);
  } catch (const omniview::cli::UsageError& e) {
    std::cerr << "omniview: " << e.what() << "\n";
    return 2;
  }
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::cout << "omniview " << OMNIVIEW_VERSION << "\n";  // the project version, from CMake
    return 0;
  }
  const std::string command = args[0];
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  try {
    // OMNIVIEW_THREADS caps the map and depth loops' threads, as for omniviewd.
    omniview::apply_worker_threads_from_env();
  } catch (const std::invalid_argument& e) {
    std::cerr << "omniview: " << e.what() << "\n";
    return 2;
  }
  try {
    const auto it = commands().find(command);
    if (it != commands().end()) return it->second(rest);
    std::cerr << "omniview: unknown command '" << command << "'\n\n" << kUsage;
    return 2;
  } catch (const omniview::cli::UsageError& e) {
    std::cerr << "omniview " << command << ": " << e.what() << "\n";
    return 2;
  } catch (const omniview::cli::RpcError& e) {
    std::cerr << "omniview " << command << ": " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "omniview " << command << ": error: " << e.what() << "\n";
    return 1;
  }
}
