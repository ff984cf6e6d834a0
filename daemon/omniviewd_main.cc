// omniviewd: serves live virtual views of a robot's cameras over gRPC.
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>

#include <malloc.h>
#include <pthread.h>

#include "core/map/worker_threads.h"
#include "server/config/daemon_config.h"
#include "server/daemon/daemon.h"
#include "server/daemon/grpc_log.h"
#include "server/source/source_registry.h"
#include "server/sources/builtin_sources.h"
#include "spot_adapter/source/spot_source.h"
#include "insta360_adapter/source/register_sources.h"

namespace {

void print_help() {
  std::cout << "usage: omniviewd --config FILE.yaml [--listen HOST:PORT] [--ready-file FILE] [--check]\n"
               "       omniviewd --version\n"
               "\n"
               "Serves live virtual views (perspective, bird's-eye, panoramas, fisheye) fused from a\n"
               "robot's cameras over gRPC (omniview.v1; grpc.health.v1 and reflection included).\n"
               "\n"
               "  --config FILE       daemon config (commented example: config/omniviewd.yaml)\n"
               "  --listen HOST:PORT  overrides the config's listen address (port 0: pick a free one);\n"
               "                      also [IPv6]:PORT or unix:/PATH (docs/SECURITY.md: what needs TLS)\n"
               "  --ready-file FILE   once serving, write the address listened on to FILE\n"
               "  --check             load the config, create its sources, views and TLS credentials\n"
               "                      as a start would (without listening), then exit (0: fine)\n"
               "  --version           the version\n"
               "  --help              this text\n"
               "\n"
               "Source types:\n";
  for (const auto& [type, help] : omniview::source_types()) std::cout << "  " << type << ": " << help << "\n";
  std::cout << "\nEnvironment: OMNIVIEW_LISTEN=HOST:PORT overrides the config's listen address (--listen wins).\n";
  std::cout << "\nEnvironment: OMNIVIEW_THREADS=N caps the threads that build and apply maps (default: all\n"
               "cores; 1: everything on the render and request threads).\n";
  std::cout << "\nStop with SIGTERM or Ctrl-C: streams end with status UNAVAILABLE, nothing hangs.\n";
}

// Image buffers of a few MB are allocated and freed on every frame set, on several
// threads. glibc's dynamic thresholds hand such buffers back to the kernel whenever a
// thread's free heap top passes twice the largest buffer seen, and the next frame faults
// every page in again: measured at ~13 % of a core for two 1024x1024 colour cameras (VMs
// make page faults dear). Fixed thresholds keep them in the heap; memory is still
// returned once 64 MB lie free at a heap's top.
void keep_image_buffers_in_the_heap() {
  mallopt(M_MMAP_THRESHOLD, 16 << 20);
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
}

}  // namespace

int main(int argc, char** argv) {
  keep_image_buffers_in_the_heap();
  omniview::limit_grpc_log_rate();
  omniview::register_builtin_sources();
  omniview::spot::register_spot_source();
  omniview::insta360::register_insta360_sources();
  std::string config_file, ready_file;
  std::optional<std::string> listen;
  bool check_only = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "omniviewd: " << arg << " needs a value (see --help)\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") {
      print_help();
      return 0;
    } else if (arg == "--version") {
      std::cout << "omniviewd " << OMNIVIEW_VERSION << "\n";  // the project version, from CMake
      return 0;
    } else if (arg == "--config") {
      config_file = value();
    } else if (arg == "--listen") {
      listen = value();
    } else if (arg == "--ready-file") {
      ready_file = value();
    } else if (arg == "--check") {
      check_only = true;
    } else {
      std::cerr << "omniviewd: unknown argument '" << arg << "' (see --help)\n";
      return 2;
    }
  }
  if (config_file.empty()) {
    std::cerr << "omniviewd: --config FILE.yaml is required (try config/omniviewd.yaml; see --help)\n";
    return 2;
  }

  // Signals are taken by sigwait() below, never delivered to a random gRPC thread: block
  // them before any thread exists so every thread inherits the mask.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  try {
    omniview::apply_worker_threads_from_env();
    // --listen, OMNIVIEW_LISTEN and the file merged, then the exposure rule: --check and a start alike.
    omniview::DaemonConfig config =
        omniview::load_daemon_config(config_file, omniview::ListenOptions::from_environment(listen));
    if (check_only) {
      // Everything the real start does but listening: sources, views, TLS credentials.
      omniview::Daemon daemon(config, /*listen=*/false);
      std::cout << config_file << ": OK (" << config.sources.size() << " sources, " << config.views.size()
                << " views)\n";
      return 0;
    }
    omniview::Daemon daemon(config);
    std::cerr << "omniviewd: listening on " << daemon.address() << (config.tls ? " (TLS" : " (plaintext")
              << (config.tokens.empty() ? ", no tokens)" : ", tokens required)") << "; views:";
    for (const auto& v : daemon.pipeline().list_views()) std::cerr << " " << v.spec().name();
    std::cerr << std::endl;
    for (const auto& url : daemon.rtsp_urls()) {
      std::cerr << "omniviewd: RTSP (H.264): " << url
                << (config.tokens.empty() ? "" : " (user omniview, a token as password)") << std::endl;
    }
    if (!daemon.web_url().empty()) {
      std::cerr << "omniviewd: console and Foxglove WebSocket on " << daemon.web_url()
                << (config.tokens.empty() ? "" : " (tokens required)") << std::endl;
      if (const std::string whep = daemon.whep_summary(); !whep.empty()) {
        std::cerr << "omniviewd: WebRTC (WHEP): " << whep << (config.tokens.empty() || whep.rfind("off:", 0) == 0 ? "" : " (tokens required)")
                  << std::endl;
      }
    }
    if (config.blackbox) {
      std::cerr << "omniviewd: black box: the last " << config.blackbox->minutes << " min of each source (at most "
                << (config.blackbox->max_bytes >> 20) << " MiB) in " << config.blackbox->folder
                << "; 'omniview blackbox save NAME' saves it" << std::endl;
    }
    // Not an error (nothing saved yet), but said: a path that resolves elsewhere than the
    // user thinks (it is relative to the config's folder) would otherwise lose views silently.
    if (std::error_code ec; !config.views_file.empty() && !std::filesystem::exists(config.views_file, ec)) {
      std::cerr << "omniviewd: views_file '" << config.views_file
                << "' does not exist (yet): serving the config's views; 'omniview views save' writes it" << std::endl;
    }
    if (!ready_file.empty()) {
      const std::string tmp = ready_file + ".tmp";
      // The gRPC address first (what scripts read), then the web endpoint's when it serves.
      std::ofstream out(tmp);
      out << daemon.address() << "\n";
      if (!daemon.web_address().empty()) out << "web " << daemon.web_address() << "\n";
      out.close();
      std::rename(tmp.c_str(), ready_file.c_str());  // appears whole, never half-written
    }
    int sig = 0;
    sigwait(&stop_signals, &sig);
    std::cerr << "omniviewd: " << strsignal(sig) << ", shutting down" << std::endl;
    daemon.shutdown();
    std::cerr << "omniviewd: stopped" << std::endl;
    return 0;
  } catch (const omniview::ConfigError& e) {
    std::cerr << "omniviewd: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "omniviewd: " << e.what() << "\n";
    return 1;
  }
}
