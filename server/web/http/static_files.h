// The console's files: URL paths mapped onto a few folders, nothing outside them ever
// served (no "..", no links out, regular files only), each with its content type.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace omniview::web {

class StaticFiles {
 public:
  // `mounts`: URL prefix ("/", "/javascript/") -> folder. The longest matching prefix wins.
  explicit StaticFiles(std::vector<std::pair<std::string, std::string>> mounts);

  struct Found {
    int status = 404;          // 200, 400 (a malformed path) or 404
    std::string file;          // the file to send when 200
    std::string content_type;  // its type
  };
  // `target`: the request target ("/index.html?x=1"); a folder serves its index.html.
  Found find(const std::string& target) const;

 private:
  std::vector<std::pair<std::string, std::string>> mounts_;
};

std::string content_type_of(const std::string& file);

// The whole of a file found above; nullopt when it cannot be read (or is over 64 MiB, which
// no console file comes near).
std::optional<std::string> read_file(const std::string& file);

}  // namespace omniview::web
