// Fuzz target: our rig YAML and kalibr camchains, as they arrive from users.
// Any input may be rejected with a ConfigError; nothing may crash, hang or leak.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/io/yaml_reader.h"
#include "core/rig/rig.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto reader = omniview::YamlReader::from_string(text, "fuzz.yaml");
    try {
      omniview::parse_rig_yaml(reader, "/nonexistent-omniview-fuzz");
    } catch (const std::exception&) {
    }
    try {
      omniview::parse_kalibr_camchain(reader, "base_link", omniview::Pose::Identity());
    } catch (const std::exception&) {
    }
  } catch (const std::exception&) {
  }
  return 0;
}
