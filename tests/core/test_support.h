// Small helpers shared by the core unit tests.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Core>
#include <atomic>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <string>

namespace omniview::testing {

constexpr double kDeg = M_PI / 180;

// Unit ray at angle `theta` from the optical axis (+z), azimuth `phi` from +x toward +y.
inline Eigen::Vector3d ray_at(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// A fresh folder under the system temp dir, removed again at the end of the test. The name
// carries pid, test and a counter, so parallel ctest runs and repeated fixtures never share.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "omniview_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
    if (info) name += std::string("_") + info->test_suite_name() + "_" + info->name();
    for (char& c : name) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
    }
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // Writes `text` to `name` (sub-folders created) and returns the full path.
  std::string write(const std::string& name, const std::string& text) const {
    const auto file = path_ / name;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << text;
    return file.string();
  }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// Runs `f`, which must throw an `E` whose message contains every needle.
template <typename E>
void expect_throw_containing(const std::function<void()>& f, std::initializer_list<std::string> needles,
                             const std::string& context = "") {
  try {
    f();
    ADD_FAILURE() << context << ": no exception; expected one mentioning " << *needles.begin();
  } catch (const E& e) {
    const std::string what = e.what();
    for (const auto& n : needles) {
      EXPECT_NE(what.find(n), std::string::npos) << context << ": message lacks '" << n << "': " << what;
    }
  }
}

}  // namespace omniview::testing
