// spot-mock: a stand-in Spot robot speaking Spot's gRPC API, for CI, demos and newcomers.
// `spot-mock [options]` serves; `spot-mock control ...` drives a running one.
#include <csignal>
#include <cstring>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <pthread.h>

#include "core/map/worker_threads.h"
#include "spot_adapter/mock/control/control_command.h"
#include "spot_adapter/mock/server/mock_server.h"

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && args.front() == "control") {
    return omniview::spot_mock::run_control_command({args.begin() + 1, args.end()});
  }
  const auto parsed = omniview::spot_mock::parse_mock_options(args);
  if (!parsed.options) return parsed.exit_code;
  const auto& options = *parsed.options;

  // Signals are taken by sigwait() below, never delivered to a random gRPC thread: block
  // them before any thread exists so every thread inherits the mask.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  try {
    omniview::apply_worker_threads_from_env();  // the start-up render honours OMNIVIEW_THREADS
    omniview::spot_mock::MockServer server(options);
    std::cout << "spot-mock listening on " << server.address() << " (certs in " << options.certs_dir << ")"
              << std::endl;
    if (!options.ready_file.empty()) {
      const std::string tmp = options.ready_file + ".tmp";
      std::ofstream(tmp) << server.address() << "\n";
      std::rename(tmp.c_str(), options.ready_file.c_str());  // appears whole, never half-written
    }
    int sig = 0;
    sigwait(&stop_signals, &sig);
    std::cerr << "spot-mock: " << strsignal(sig) << ", shutting down" << std::endl;
    server.shutdown(std::chrono::seconds(2));
    std::cerr << "spot-mock: stopped" << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "spot-mock: " << e.what() << "\n";
    return 1;
  }
}
