#include "spot_adapter/mock/sensors/render_cache.h"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <stdexcept>
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

fs::path item_file(const fs::path& entry, size_t index, const std::string& extension) {
  return entry / ("camera_" + std::to_string(index) + extension);
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

template <typename Item, typename ReadItem>
std::optional<std::vector<Item>> RenderCache::load_items(const std::string& extension, ReadItem read_item) const {
  std::ifstream key_file(entry_ / "key");
  std::string stored_key;
  size_t count = 0;
  if (!std::getline(key_file, stored_key) || stored_key != key_ || !(key_file >> count) || count == 0) {
    return std::nullopt;
  }
  std::vector<Item> items;
  for (size_t i = 0; i < count; ++i) {
    std::optional<Item> item = read_item(item_file(entry_, i, extension));
    if (!item) return std::nullopt;
    items.push_back(std::move(*item));
  }
  return items;
}

template <typename WriteItem>
void RenderCache::store_items(size_t count, const std::string& extension, WriteItem write_item) const {
  std::error_code ec;
  fs::create_directories(folder_, ec);
  prune_old_entries(folder_);
  const fs::path staging = entry_.string() + ".tmp-" + std::to_string(::getpid());
  fs::remove_all(staging, ec);
  fs::create_directories(staging, ec);
  bool written = !ec;
  for (size_t i = 0; written && i < count; ++i) {
    try {
      write_item(item_file(staging, i, extension), i);
    } catch (const std::exception& e) {
      std::cerr << "spot-mock: render cache: " << e.what() << "\n";
      written = false;
    }
  }
  if (written) {
    std::ofstream key_file(staging / "key");
    key_file << key_ << "\n" << count << "\n";
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

std::optional<std::vector<cv::Mat>> RenderCache::load() const {
  return load_items<cv::Mat>(".png", [](const fs::path& file) -> std::optional<cv::Mat> {
    std::string why;
    cv::Mat picture = read_image(file, ImageColour::kAsStored, &why);
    if (picture.empty()) return std::nullopt;
    return picture;
  });
}

void RenderCache::store(const std::vector<cv::Mat>& pictures) const {
  store_items(pictures.size(), ".png", [&](const fs::path& file, size_t i) { write_image(file, pictures[i]); });
}

std::optional<std::vector<std::string>> RenderCache::load_bytes() const {
  return load_items<std::string>(".bin", [](const fs::path& file) -> std::optional<std::string> {
    std::ifstream in(file, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (!in && !in.eof()) return std::nullopt;
    return std::move(bytes).str();
  });
}

void RenderCache::store_bytes(const std::vector<std::string>& items) const {
  store_items(items.size(), ".bin", [&](const fs::path& file, size_t i) {
    std::ofstream out(file, std::ios::binary);
    out.write(items[i].data(), static_cast<std::streamsize>(items[i].size()));
    if (!out.flush()) throw std::runtime_error("cannot write " + file.string());
  });
}

}  // namespace omniview::spot_mock
