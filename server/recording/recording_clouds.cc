// A recording's lidar clouds: clouds.csv (the index) and clouds/<frame>.pcd (layout in
// recording_writer.cc).
#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/cloud/cloud_file.h"
#include "core/io/yaml_reader.h"
#include "server/recording/recording.h"

namespace omniview {
namespace fs = std::filesystem;
namespace {

template <typename T>
bool parse_csv_integer(const std::string& text, T& value) {
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  return !text.empty() && result.ec == std::errc() && result.ptr == end;
}

}  // namespace

void parse_recording_clouds(const std::string& clouds_csv, const std::string& file,
                            std::vector<RecordingFrame>& frames) {
  size_t line_number = 0;
  const auto fail = [&](const std::string& message) {
    throw ConfigError(file + ":" + std::to_string(line_number) + ": " + message);
  };
  size_t start = 0;
  for (size_t end; (end = clouds_csv.find('\n', start)) != std::string::npos; start = end + 1) {
    ++line_number;
    std::string line = clouds_csv.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_number == 1) {
      if (line != "frame,stamp_ns,file") fail("header must read 'frame,stamp_ns,file'");
      continue;
    }
    const size_t a = line.find(','), b = a == std::string::npos ? a : line.find(',', a + 1);
    if (b == std::string::npos || line.find(',', b + 1) != std::string::npos) {
      fail("expected 3 fields (frame, stamp_ns, file)");
    }
    const std::string frame_text = line.substr(0, a), stamp_text = line.substr(a + 1, b - a - 1);
    const std::string path = line.substr(b + 1);
    size_t frame = 0;
    int64_t ns = 0;
    if (!parse_csv_integer(frame_text, frame)) fail("frame '" + frame_text + "' is not a number");
    if (!parse_csv_integer(stamp_text, ns)) fail("stamp_ns '" + stamp_text + "' is not a number");
    // The file must be one the writer names: clouds/<frame>.pcd, inside the recording.
    if (path != "clouds/" + frame_text + ".pcd") fail("file '" + path + "' must be 'clouds/" + frame_text + ".pcd'");
    // A cloud of a frame whose frames.csv line was cut short: nothing to attach it to.
    if (frame >= frames.size()) continue;
    frames[frame].cloud_file = path;
    frames[frame].cloud_stamp = std::chrono::system_clock::time_point(
        std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::nanoseconds(ns)));
  }
}

std::shared_ptr<PointCloud> Recording::load_cloud(const RecordingFrame& frame) const {
  if (frame.cloud_file.empty()) return nullptr;
  const std::string path = (fs::path(folder) / frame.cloud_file).string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open the cloud of frame " + std::to_string(frame.sequence));
  std::ostringstream bytes;
  bytes << in.rdbuf();
  try {
    auto cloud = std::make_shared<PointCloud>(parse_pcd(bytes.str(), path));
    cloud->stamp = frame.cloud_stamp;  // the index's stamp is the one the writer had
    return cloud;
  } catch (const CloudFormatError& e) {
    throw std::runtime_error(e.what());
  }
}

bool Recording::has_clouds() const {
  for (const auto& frame : frames) {
    if (!frame.cloud_file.empty()) return true;
  }
  return false;
}

}  // namespace omniview
