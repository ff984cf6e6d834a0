// `blackbox:` — how many minutes of the sources the daemon keeps on disk, in how many bytes
// at most, and where.
#include <cctype>
#include <cmath>
#include <string>

#include "server/config/config_parts.h"

namespace omniview::config_parts {
namespace {

// Below this a ring holds a few seconds of one robot camera at most: a typo, not a choice.
constexpr uint64_t kMinBlackBoxBytes = uint64_t{4} << 20;

// "2G", "500M", "750MB", "64MiB" or a plain number of bytes (units of 1024).
uint64_t parse_bytes(const YamlReader& r, const YAML::Node& n, const std::string& path) {
  const std::string bad = "expected a size in bytes, or with a unit: 500M, 2G (K, M, G, T; powers of 1024)";
  std::string text = r.text(n, path);
  size_t end = 0;
  double value = 0;
  try {
    value = std::stod(text, &end);
  } catch (const std::exception&) {
    r.fail(n, path, bad + ", got '" + text + "'");
  }
  std::string unit = text.substr(end);
  while (!unit.empty() && unit.front() == ' ') unit.erase(unit.begin());
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();
  if (unit.size() > 1 && unit.back() == 'I') unit.pop_back();  // MiB, GiB
  double scale = 1;
  if (unit == "K") scale = 1024.0;
  else if (unit == "M") scale = 1024.0 * 1024;
  else if (unit == "G") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
  else if (!unit.empty() && unit != "B") r.fail(n, path, bad + ", got '" + text + "'");
  const double bytes = value * scale;
  if (!std::isfinite(bytes) || bytes < double(kMinBlackBoxBytes) || bytes > 1e15) {
    r.fail(n, path, "must be from 4M to 1000T, got '" + text + "'");
  }
  return static_cast<uint64_t>(bytes);
}

}  // namespace

BlackBoxConfig parse_blackbox(const YamlReader& r, const YAML::Node& n, const std::string& folder) {
  BlackBoxConfig box;
  if (!n.IsMap()) r.fail(n, "blackbox", "expected a map: {minutes: 5, max_bytes: 2G, folder: blackbox}");
  r.expect_keys(n, "blackbox", {"minutes", "max_bytes", "folder"});
  box.node = n;
  if (n["minutes"]) {
    box.minutes = r.number(n["minutes"], "blackbox.minutes");
    if (!(box.minutes >= 0.1 && box.minutes <= 24 * 60)) {
      r.fail(n["minutes"], "blackbox.minutes", "must be from 0.1 to 1440 (a day)");
    }
  }
  if (n["max_bytes"]) box.max_bytes = parse_bytes(r, n["max_bytes"], "blackbox.max_bytes");
  box.folder = resolve_config_path(folder, n["folder"] ? r.text(n["folder"], "blackbox.folder") : "blackbox");
  if (n["folder"] && r.text(n["folder"], "blackbox.folder").empty()) {
    r.fail(n["folder"], "blackbox.folder", "must not be empty");
  }
  return box;
}

}  // namespace omniview::config_parts
