#include "server/source/source_registry.h"

#include <map>
#include <mutex>

namespace omniview {

namespace {

struct Entry {
  std::string help;
  SourceFactory factory;
};

std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}

std::map<std::string, Entry>& registry() {
  static std::map<std::string, Entry> r;
  return r;
}

}  // namespace

void register_source_type(const std::string& type, const std::string& help, SourceFactory factory) {
  std::lock_guard lock(registry_mutex());
  registry()[type] = Entry{help, std::move(factory)};
}

std::unique_ptr<Source> make_source(const std::string& type, const SourceConfig& config) {
  SourceFactory factory;
  {
    std::lock_guard lock(registry_mutex());
    const auto it = registry().find(type);
    if (it == registry().end()) {
      std::string known;
      for (const auto& [name, _] : registry()) known += (known.empty() ? "" : ", ") + name;
      const std::string message = "unknown source type '" + type + "' (known: " + known + ")";
      if (config.reader) config.reader->fail(config.node["type"], config.path + ".type", message);
      throw ConfigError(config.name + ": " + message);
    }
    factory = it->second.factory;
  }
  return factory(config);
}

std::vector<std::pair<std::string, std::string>> source_types() {
  std::lock_guard lock(registry_mutex());
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [name, entry] : registry()) out.emplace_back(name, entry.help);
  return out;
}

}  // namespace omniview
