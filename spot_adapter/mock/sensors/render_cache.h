// A folder of rendered camera pictures that spot-mock reuses across starts.
//
// Ray casting the five cameras is nearly all of the mock's start-up: ~0.7 s in a release
// build, but 6-15 s under AddressSanitizer or ThreadSanitizer, and the test suites start the
// mock some 40 times per sanitizer tree. The pictures depend only on the scene, the colour
// mode, the supersampling and the program that rendered them, so an entry is keyed by those
// (the program by its executable's size and modification time: any rebuild makes new
// entries, a stale picture is never served). Entries are written to a temporary folder and
// renamed into place, so mocks starting side by side never read half an entry.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace omniview::spot_mock {

class RenderCache {
 public:
  // `key` names everything the pictures depend on besides the program (scene, colour, ...).
  RenderCache(std::filesystem::path folder, const std::string& key);

  // The cached pictures, or nullopt when there are none (or they cannot be read: then the
  // caller renders anew, and store() replaces the entry).
  std::optional<std::vector<cv::Mat>> load() const;
  // Saves `pictures` (CV_8UC1 or CV_8UC3). A failure to write is reported on stderr and
  // otherwise ignored: the cache only saves time.
  void store(const std::vector<cv::Mat>& pictures) const;

  // The same for data that is no picture (the depth images' wire bytes): one file each.
  std::optional<std::vector<std::string>> load_bytes() const;
  void store_bytes(const std::vector<std::string>& items) const;

  const std::filesystem::path& entry() const { return entry_; }

 private:
  std::filesystem::path folder_;
  std::string key_;  // the full key, kept in the entry to guard against hash collisions
  std::filesystem::path entry_;

  // Reads `count` items with `read_item(file, index)`; nullopt if the entry is missing or any fails.
  template <typename Item, typename ReadItem>
  std::optional<std::vector<Item>> load_items(const std::string& extension, ReadItem read_item) const;
  // Writes `count` items with `write_item(file, index)` (throws on failure) under a staging
  // folder and renames it into place.
  template <typename WriteItem>
  void store_items(size_t count, const std::string& extension, WriteItem write_item) const;
};

}  // namespace omniview::spot_mock
