// Fuzz target: a recording's index (recording.yaml + frames.csv, joints.csv and clouds.csv),
// which the replay source reads from disk. Input: recording.yaml's text, a line "=====",
// frames.csv's text, optionally another line "=====" and joints.csv's text, and another
// "=====" and clouds.csv's text.
// A ConfigError is the expected answer to bad input; anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/io/yaml_reader.h"
#include "server/recording/recording.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::string separator = "\n=====\n";
  const size_t split = input.find(separator);
  const std::string yaml = input.substr(0, split);
  std::string csv = split == std::string::npos ? "" : input.substr(split + separator.size());
  const size_t joints_split = csv.find(separator);
  std::string joints = joints_split == std::string::npos ? "" : csv.substr(joints_split + separator.size());
  if (joints_split != std::string::npos) csv.resize(joints_split + 1);  // keep the last line's newline
  const size_t clouds_split = joints.find(separator);
  const std::string clouds = clouds_split == std::string::npos ? "" : joints.substr(clouds_split + separator.size());
  if (clouds_split != std::string::npos) joints.resize(clouds_split + 1);
  try {
    auto index = omniview::parse_recording_index(yaml, csv, "fuzz");
    // What Recording::open and the replay source rely on after a successful parse.
    if (index.frames.empty() || index.camera_names.empty()) std::abort();
    for (const auto& frame : index.frames) {
      if (frame.rig_index >= index.rig_count || frame.image_files.size() != index.camera_names.size()) std::abort();
      for (const auto& file : frame.image_files) {
        if (!file.empty() && file[0] == '/') std::abort();
        for (const auto& part : std::filesystem::path(file)) {
          if (part == "..") std::abort();  // must stay inside the recording folder
        }
      }
    }
    omniview::parse_recording_joints(joints, "fuzz/joints.csv", index.frames);
    for (const auto& frame : index.frames) {
      if (!frame.joints) continue;
      for (const auto& [name, position] : *frame.joints) {
        if (name.empty() || !std::isfinite(position)) std::abort();
      }
    }
    omniview::parse_recording_clouds(clouds, "fuzz/clouds.csv", index.frames);
    for (const auto& frame : index.frames) {
      if (frame.cloud_file.empty()) continue;
      // Only the writer's own names: inside the recording's clouds/ folder.
      if (frame.cloud_file.rfind("clouds/", 0) != 0 || frame.cloud_file.find("..") != std::string::npos ||
          frame.cloud_file.find('/', 7) != std::string::npos) {
        std::abort();
      }
    }
  } catch (const omniview::ConfigError&) {
  }
  return 0;
}
