// `omniview blackbox save NAME [--source S]`: the daemon's black box (its last minutes of
// each source) saved as a recording on the daemon's machine. `omniview status` shows the
// ring itself.
#include <cstdio>
#include <iostream>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"

namespace omniview::cli {
namespace {

const std::string kBlackBoxHelp = std::string(R"(usage: omniview blackbox save NAME [--source SOURCE]

The daemon keeps the last minutes of what its sources deliver (camera images, clouds,
joints, rig) when its config has a `blackbox:` block, and saves them by itself when a
robot's connection drops. This saves them now, as NAME in the black box's snapshots
folder on the daemon's machine (needs an operator token): an ordinary recording, to replay
(a `replay` source) or to export (omniview export FOLDER -o FILE.mcap).

  --source SOURCE   only this source's ring (default: every source's)

NAME: 1-64 letters, digits, '.', '_' or '-', starting with a letter or digit. The daemon
prints where it saved (folder/snapshots/NAME on its machine, the folder relative to its
config file). 'omniview status' shows what the ring holds.

)") + connection_help();

std::string mebibytes(uint64_t bytes) {  // as the config's max_bytes and `omniview status` count
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / (1 << 20));
  return text;
}

}  // namespace

int blackbox_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(argv, {}, {"source"}, kBlackBoxHelp);
  if (!args) return 0;
  if (args->positional().empty() || args->positional()[0] != "save") {
    throw UsageError("expected 'omniview blackbox save NAME' (see --help)");
  }
  expect_positional(*args, 2, "save NAME");
  v1::SaveBlackBoxRequest request;
  request.set_name(args->positional()[1]);
  request.set_source(args->get("source"));
  Connection connection(connection_options(*args));
  grpc::ClientContext context;
  connection.prepare(context, true);
  // Copying minutes of images takes seconds: longer than a unary call's usual deadline.
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::minutes(10));
  v1::SaveBlackBoxResponse response;
  connection.check(connection.stub().SaveBlackBox(&context, request, &response), "");
  for (const auto& s : response.snapshots()) {
    std::cout << "saved source '" << s.source() << "': " << s.frame_sets() << " frame sets, " << fixed(s.span_s(), 1)
              << " s, " << mebibytes(s.bytes()) << " in " << s.folder() << " (on the daemon's machine)\n";
    if (!s.note().empty()) std::cout << "  note: " << s.note() << "\n";
  }
  return 0;
}

}  // namespace omniview::cli
