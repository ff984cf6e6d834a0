// Helpers for the source tests: configs from YAML text, and a callback that collects.
#pragma once

#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "server/source/source_registry.h"

namespace omniview::testing {

// A source's YAML map as the daemon config would hand it over ("daemon.yaml", sources[0]).
struct TestConfig {
  explicit TestConfig(const std::string& yaml, std::string folder = "")
      : reader(YamlReader::from_string(yaml, "daemon.yaml")) {
    config.name = "test";
    config.reader = &reader;
    config.node = reader.root();
    config.path = "sources[0]";
    config.folder = std::move(folder);
  }
  YamlReader reader;
  SourceConfig config;
};

// The ConfigError message `make` throws, or "" when it does not.
template <typename Make>
std::string config_error(Make make) {
  try {
    make();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

// Collects delivered frame sets with their arrival times.
class Collector {
 public:
  Source::FrameCallback callback() {
    return [this](std::shared_ptr<const FrameSet> frames) {
      std::lock_guard lock(mutex_);
      frames_.push_back(std::move(frames));
      arrived_.notify_all();
    };
  }
  // Waits until `count` frame sets arrived (or `timeout` passed); returns a copy.
  std::vector<std::shared_ptr<const FrameSet>> wait_for(size_t count, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    arrived_.wait_for(lock, timeout, [&] { return frames_.size() >= count; });
    return frames_;
  }
  size_t count() {
    std::lock_guard lock(mutex_);
    return frames_.size();
  }

 private:
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<std::shared_ptr<const FrameSet>> frames_;
};

// A temporary folder for one test, removed afterwards.
class TempFolder {
 public:
  TempFolder() {
    path_ = std::filesystem::temp_directory_path() /
            ("omniview_sources_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempFolder() { std::filesystem::remove_all(path_); }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  std::string str() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace omniview::testing
