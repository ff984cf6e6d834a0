// omniview: the command-line tool. Subcommands live in their own files.
#include <iostream>
#include <string>
#include <vector>

#include "cli/args.h"
#include "cli/render_command.h"
#include "core/io/yaml_reader.h"

namespace {

constexpr const char* kUsage = R"(usage: omniview COMMAND [options]

commands:
  render    compute views offline from a rig and images (omniview render --help)

Run 'omniview COMMAND --help' for a command's options.
)";

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::cout << kUsage;
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  try {
    if (command == "render") return omniview::cli::render_command(rest);
    std::cerr << "omniview: unknown command '" << command << "'\n\n" << kUsage;
    return 2;
  } catch (const omniview::cli::UsageError& e) {
    std::cerr << "omniview " << command << ": " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "omniview " << command << ": error: " << e.what() << "\n";
    return 1;
  }
}
