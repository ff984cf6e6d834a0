#include "server/web/http/static_files.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace omniview::web {
namespace fs = std::filesystem;

namespace {

// "%2e%2e" must not sneak past the ".." check: decode first, refuse what does not decode.
bool percent_decode(const std::string& in, std::string& out) {
  out.clear();
  for (size_t i = 0; i < in.size(); ++i) {
    if (in[i] != '%') {
      out += in[i];
      continue;
    }
    if (i + 2 >= in.size() || !std::isxdigit(static_cast<unsigned char>(in[i + 1])) ||
        !std::isxdigit(static_cast<unsigned char>(in[i + 2]))) {
      return false;
    }
    out += static_cast<char>(std::stoi(in.substr(i + 1, 2), nullptr, 16));
    i += 2;
  }
  return out.find('\0') == std::string::npos;
}

bool under(const fs::path& file, const fs::path& folder) {
  const auto f = file.lexically_normal().string();
  const auto d = folder.lexically_normal().string();
  return f.size() > d.size() && f.compare(0, d.size(), d) == 0 && (d.back() == '/' || f[d.size()] == '/');
}

}  // namespace

StaticFiles::StaticFiles(std::vector<std::pair<std::string, std::string>> mounts) : mounts_(std::move(mounts)) {
  std::sort(mounts_.begin(), mounts_.end(),
            [](const auto& a, const auto& b) { return a.first.size() > b.first.size(); });
}

StaticFiles::Found StaticFiles::find(const std::string& target) const {
  std::string path;
  if (!percent_decode(target.substr(0, target.find_first_of("?#")), path) || path.empty() || path[0] != '/') {
    return {400, "", ""};
  }
  // Any ".." segment is refused outright, whatever it would resolve to.
  for (size_t start = 0; start < path.size();) {
    const size_t end = std::min(path.find('/', start), path.size());
    if (path.compare(start, end - start, "..") == 0 && end - start == 2) return {400, "", ""};
    start = end + 1;
  }
  for (const auto& [prefix, folder] : mounts_) {
    if (path.compare(0, prefix.size(), prefix) != 0) continue;
    if (folder.empty()) return {404, "", ""};
    std::error_code ec;
    const fs::path root = fs::canonical(folder, ec);
    if (ec) return {404, "", ""};
    fs::path file = root / path.substr(prefix.size());
    if (fs::is_directory(file, ec)) file /= "index.html";
    const fs::path real = fs::canonical(file, ec);  // links resolved: they must stay inside too
    if (ec || !under(real, root) || !fs::is_regular_file(real, ec)) return {404, "", ""};
    return {200, real.string(), content_type_of(real.string())};
  }
  return {404, "", ""};
}

std::string content_type_of(const std::string& file) {
  static const std::pair<const char*, const char*> kTypes[] = {
      {".html", "text/html; charset=utf-8"}, {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"}, {".css", "text/css; charset=utf-8"},
      {".json", "application/json"}, {".svg", "image/svg+xml"}, {".png", "image/png"},
      {".jpg", "image/jpeg"}, {".ico", "image/x-icon"}, {".txt", "text/plain; charset=utf-8"}};
  const std::string ext = fs::path(file).extension().string();
  for (const auto& [e, type] : kTypes) {
    if (ext == e) return type;
  }
  return "application/octet-stream";
}

std::optional<std::string> read_file(const std::string& file) {
  constexpr std::uintmax_t kMaxBytes = 64u << 20;
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec || size > kMaxBytes) return std::nullopt;
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  // Exactly the size found: a read cut short (an error, the file shrinking) is no file,
  // never a truncated 200; bytes appended meanwhile are not sent.
  std::string bytes(static_cast<size_t>(size), '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size))) return std::nullopt;
  return bytes;
}

}  // namespace omniview::web
