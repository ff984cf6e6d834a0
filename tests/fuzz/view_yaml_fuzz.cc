// Fuzz target: view definitions (CLI files, and later the daemon config and API).
// Every accepted view must also survive construction and a few pixel <-> point round trips.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/io/yaml_reader.h"
#include "core/view/view.h"
#include "core/view/view_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto reader = omniview::YamlReader::from_string(text, "fuzz.yaml");
    for (const auto& spec : omniview::parse_views(reader)) {
      const auto view = omniview::View::create(spec);
      for (double f : {0.0, 0.25, 0.5, 0.999}) {
        omniview::Vec3 p;
        omniview::Vec2 uv;
        if (view->pixel_to_point(f * view->width(), f * view->height(), p)) view->point_to_pixel(p, uv);
      }
    }
  } catch (const std::exception&) {
  }
  return 0;
}
