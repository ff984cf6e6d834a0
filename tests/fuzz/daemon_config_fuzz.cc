// Fuzz target: omniviewd's config file. A ConfigError is the expected answer to bad input;
// any other exception (or a crash) is a bug. Tokens and TLS files name paths that do not
// exist here, so those branches end in ConfigError too, as they should.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "server/config/daemon_config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto reader = omniview::YamlReader::from_string(text, "fuzz.yaml");
    const auto config = omniview::parse_daemon_config(reader, "/nonexistent-omniview-fuzz");
    // What the daemon relies on after a successful parse.
    if (config.sources.empty()) std::abort();
    for (const auto& view : config.views) {
      if (view.source.empty() || int64_t{view.width} * view.height > config.limits.max_view_pixels) std::abort();
    }
    if (!config.allow_insecure_remote && !omniview::is_loopback_address(config.listen) &&
        !(config.tls && !config.tokens.empty())) {
      std::abort();
    }
  } catch (const omniview::ConfigError&) {
  }
  return 0;
}
