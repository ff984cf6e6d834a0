// Fuzz target: omniviewd's config file. A ConfigError is the expected answer to bad input;
// any other exception (or a crash) is a bug. Tokens and TLS files name paths that do not
// exist here, so those branches end in ConfigError too, as they should.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "server/config/daemon_config.h"

namespace {

// Host names never reach DNS while fuzzing (slow, and not this parser's business): only
// "localhost" resolves.
std::vector<std::string> resolve_offline(const std::string& host, std::string* error) {
  if (host == "localhost") return {"127.0.0.1", "::1"};
  *error = "not resolved while fuzzing";
  return {};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto reader = omniview::YamlReader::from_string(text, "fuzz.yaml");
    omniview::ListenOptions listen;
    listen.resolve = resolve_offline;
    const auto config = omniview::parse_daemon_config(reader, "/nonexistent-omniview-fuzz", listen);
    // What the daemon relies on after a successful parse.
    if (config.sources.empty()) std::abort();
    for (const auto& view : config.views) {
      if (view.source.empty() || int64_t{view.width} * view.height > config.limits.max_view_pixels) std::abort();
    }
    // The exposure rule held: whatever was accepted is acceptable.
    const omniview::EndpointGuards endpoint{config.listen, config.tls.has_value(), !config.tokens.empty(),
                                            config.allow_insecure_remote};
    if (!omniview::exposure_refusal(endpoint, resolve_offline).empty()) std::abort();
  } catch (const omniview::ConfigError&) {
  }
  return 0;
}
