#include "spot_adapter/mock/sensors/render_cache.h"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <system_error>

#include "core/io/image_codec.h"

namespace omniview::spot_mock {
namespace fs = std::filesystem;

namespace {

// The running program, as its executable's size and modification time: a rebuilt mock (or
// test program, for the in-process mock) never reads pictures an older build rendered.
std::string program_identity() {
  struct stat st {};
  if (::stat("/proc/self/exe", &st) != 0) return "unknown-program";
  std::ostringstream id;
  id << st.st_size << "@" << st.st_mtim.tv_sec << "." << st.st_mtim.tv_nsec;
  return id.str();
}

std::string hex(size_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016zx", value);
  return text;
}

fs::path picture_file(const fs::path& entry, size_t camera) {
  return entry / ("camera_" + std::to_string(camera) + ".png");
}

// Entries nobody has written for a week belong to builds long gone.
void prune_old_entries(const fs::path& folder) {
  std::error_code ec;
  const auto cutoff = fs::file_time_type::clock::now() - std::chrono::hours(24 * 7);
  for (const auto& item : fs::directory_iterator(folder, ec)) {
    std::error_code item_ec;
    if (item.is_directory(item_ec) && item.last_write_time(item_ec) < cutoff && !item_ec) {
      fs::remove_all(item.path(), item_ec);
    }
  }
}

}  // namespace

RenderCache::RenderCache(fs::path folder, const std::string& key)
    : folder_(std::move(folder)), key_(key + "|" + program_identity()) {
  entry_ = folder_ / hex(std::hash<std::string>{}(key_));
}

std::optional<std::vector<cv::Mat>> RenderCache::load() const {
  std::ifstream key_file(entry_ / "key");
  std::string stored_key;
  size_t count = 0;
  if (!std::getline(key_file, stored_key) || stored_key != key_ || !(key_file >> count) || count == 0) {
    return std::nullopt;
  }
  std::vector<cv::Mat> pictures;
  for (size_t i = 0; i < count; ++i) {
    std::string why;
    cv::Mat picture = read_image(picture_file(entry_, i), ImageColour::kAsStored, &why);
    if (picture.empty()) return std::nullopt;
    pictures.push_back(std::move(picture));
  }
  return pictures;
}

void RenderCache::store(const std::vector<cv::Mat>& pictures) const {
  std::error_code ec;
  fs::create_directories(folder_, ec);
  prune_old_entries(folder_);
  const fs::path staging = entry_.string() + ".tmp-" + std::to_string(::getpid());
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  bool written = !ec;
  for (size_t i = 0; written && i < pictures.size(); ++i) {
    try {
      write_image(picture_file(staging, i), pictures[i]);
    } catch (const std::exception& e) {
      std::cerr << "spot-mock: render cache: " << e.what() << "\n";
      written = false;
    }
  }
  if (written) {
    std::ofstream key_file(staging / "key");
    key_file << key_ << "\n" << pictures.size() << "\n";
    written = static_cast<bool>(key_file.flush());
  }
  if (written) {
    fs::remove_all(entry_, ec);        // an unreadable entry load() refused, if any
    fs::rename(staging, entry_, ec);   // fails if another mock just stored it: theirs stands
    written = !ec || fs::exists(entry_ / "key");
  }
  if (!written) std::cerr << "spot-mock: cannot write the render cache " << entry_ << " (rendering each start)\n";
  fs::remove_all(staging, ec);
}

}  // namespace omniview::spot_mock
