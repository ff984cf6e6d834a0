// `omniview record` in a build without the recording library (while it is being written).
#include <algorithm>
#include <iostream>

#include "cli/args.h"
#include "cli/client/client_commands.h"

namespace omniview::cli {

int record_command(const std::vector<std::string>& args) {
  constexpr const char* kNote = "this omniview was built without recording support (library omniview_recording)";
  if (std::find(args.begin(), args.end(), "--help") != args.end() ||
      std::find(args.begin(), args.end(), "-h") != args.end()) {
    std::cout << "usage: omniview record -o DIR [--source NAME] [--frames N | --duration S]\n\n"
              << kNote << "\n(connection options as for the other commands: --server, --tls-ca, --token-file)\n";
    return 0;
  }
  throw std::runtime_error(kNote);
}

}  // namespace omniview::cli
