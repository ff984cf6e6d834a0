// Reading a recording: the index (recording.yaml, frames.csv), its rigs and images.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/io/image_codec.h"
#include "core/io/yaml_reader.h"
#include "server/recording/recording.h"

namespace omniview {
namespace fs = std::filesystem;
namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> fields;
  size_t start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma - start));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

template <typename T>
bool parse_integer(const std::string& text, T& value) {
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  return !text.empty() && result.ec == std::errc() && result.ptr == end;
}

// Image paths must stay inside the recording folder.
bool safe_relative_path(const std::string& file) {
  if (file.empty() || file[0] == '/' || file.find('\\') != std::string::npos) return false;
  for (const auto& part : fs::path(file)) {
    if (part == "..") return false;
  }
  return true;
}

std::string read_text_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path.string() + ": cannot open (not a recording folder?)");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void parse_header(const YamlReader& r, RecordingIndex& index) {
  const YAML::Node& root = r.root();
  if (!root.IsMap()) r.fail(root, "", "expected a map with format, version, source, cameras");
  r.expect_keys(root, "", {"format", "version", "source", "cameras", "created"});
  if (r.text(r.required(root, "format", ""), "format") != "omniview-recording") {
    r.fail(root["format"], "format", "not an omniview recording (expected 'omniview-recording')");
  }
  if (r.integer(r.required(root, "version", ""), "version") != 1) {
    r.fail(root["version"], "version", "unsupported recording version (this build reads version 1)");
  }
  index.source_name = root["source"] ? r.text(root["source"], "source") : "";
  const YAML::Node cams = r.required(root, "cameras", "");
  if (!cams.IsSequence() || cams.size() == 0) r.fail(cams, "cameras", "expected a non-empty list of camera names");
  for (size_t i = 0; i < cams.size(); ++i) {
    index.camera_names.push_back(r.text(cams[i], "cameras[" + std::to_string(i) + "]"));
  }
}

// The format an image file's name says ("" for one we would not store as is).
std::string image_format_of(const std::string& file) {
  const std::string ext = fs::path(file).extension().string();
  if (ext == ".jpg" || ext == ".jpeg") return "jpeg";
  if (ext == ".png") return "png";
  return "";
}

}  // namespace

std::string recording_rig_file(size_t index) {
  return index == 0 ? "rig.yaml" : "rig_" + std::to_string(index) + ".yaml";
}

RecordingIndex parse_recording_index(const std::string& recording_yaml, const std::string& frames_csv,
                                     const std::string& folder) {
  RecordingIndex index;
  parse_header(YamlReader::from_string(recording_yaml, (fs::path(folder) / "recording.yaml").string()), index);
  const std::string csv_name = (fs::path(folder) / "frames.csv").string();
  size_t line_number = 0;
  const auto fail = [&](const std::string& message) {
    throw ConfigError(csv_name + ":" + std::to_string(line_number) + ": " + message);
  };
  size_t start = 0;
  // Only complete lines: a last line without its newline was cut short and is ignored.
  for (size_t end; (end = frames_csv.find('\n', start)) != std::string::npos; start = end + 1) {
    ++line_number;
    std::string line = frames_csv.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto fields = split_csv_line(line);
    if (line_number == 1) {
      std::string expected = "sequence,capture_time_ns,rig";
      for (const auto& name : index.camera_names) expected += "," + name;
      if (line != expected) fail("header must read '" + expected + "' (the cameras of recording.yaml)");
      continue;
    }
    if (fields.size() != 3 + index.camera_names.size()) {
      fail("expected " + std::to_string(3 + index.camera_names.size()) + " fields, got " +
           std::to_string(fields.size()));
    }
    RecordingFrame frame;
    int64_t ns = 0;
    if (!parse_integer(fields[0], frame.sequence)) fail("sequence '" + fields[0] + "' is not a number");
    if (!parse_integer(fields[1], ns)) fail("capture_time_ns '" + fields[1] + "' is not a number");
    if (!parse_integer(fields[2], frame.rig_index)) fail("rig '" + fields[2] + "' is not a number");
    // Rigs are numbered as they appear: a frame names a known rig or the next one.
    if (frame.rig_index > index.rig_count) fail("rig " + fields[2] + " skips rig " + std::to_string(index.rig_count));
    index.rig_count = std::max(index.rig_count, frame.rig_index + 1);
    if (!index.frames.empty() && frame.sequence <= index.frames.back().sequence) {
      fail("sequence " + fields[0] + " does not increase");
    }
    frame.capture_time = std::chrono::system_clock::time_point(
        std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::nanoseconds(ns)));
    for (size_t i = 3; i < fields.size(); ++i) {
      if (!fields[i].empty() && !safe_relative_path(fields[i])) {
        fail("image path '" + fields[i] + "' must be relative and inside the recording");
      }
      frame.image_files.push_back(fields[i]);
    }
    index.frames.push_back(std::move(frame));
  }
  if (line_number == 0) throw ConfigError(csv_name + ": empty (no header line)");
  if (index.frames.empty()) throw ConfigError(csv_name + ": no complete frame");
  return index;
}

void parse_recording_joints(const std::string& joints_csv, const std::string& file,
                            std::vector<RecordingFrame>& frames) {
  std::vector<std::map<std::string, double>> joints(frames.size());
  size_t line_number = 0;
  const auto fail = [&](const std::string& message) {
    throw ConfigError(file + ":" + std::to_string(line_number) + ": " + message);
  };
  size_t start = 0;
  for (size_t end; (end = joints_csv.find('\n', start)) != std::string::npos; start = end + 1) {
    ++line_number;
    std::string line = joints_csv.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_number == 1) {
      if (line != "frame,joint,position") fail("header must read 'frame,joint,position'");
      continue;
    }
    const auto fields = split_csv_line(line);
    if (fields.size() != 3) fail("expected 3 fields (frame, joint, position), got " + std::to_string(fields.size()));
    size_t frame = 0;
    if (!parse_integer(fields[0], frame)) fail("frame '" + fields[0] + "' is not a number");
    if (fields[1].empty()) fail("empty joint name");
    double position = 0;
    const char* text_end = fields[2].data() + fields[2].size();
    const auto parsed = std::from_chars(fields[2].data(), text_end, position);
    if (fields[2].empty() || parsed.ec != std::errc() || parsed.ptr != text_end || !std::isfinite(position)) {
      fail("position '" + fields[2] + "' is not a finite number");
    }
    // Joints of a frame whose frames.csv line was cut short: nothing to attach them to.
    if (frame >= frames.size()) continue;
    joints[frame][fields[1]] = position;
  }
  for (size_t i = 0; i < frames.size(); ++i) {
    if (!joints[i].empty()) frames[i].joints = std::make_shared<const std::map<std::string, double>>(std::move(joints[i]));
  }
}

Recording Recording::open(const std::string& folder) {
  const fs::path dir(folder);
  if (!fs::is_directory(dir)) throw ConfigError(folder + ": no such recording folder");
  const std::string header = read_text_file(dir / "recording.yaml");
  RecordingIndex index = parse_recording_index(header, read_text_file(dir / "frames.csv"), folder);
  Recording recording;
  recording.folder = folder;
  recording.source_name = std::move(index.source_name);
  recording.camera_names = std::move(index.camera_names);
  recording.frames = std::move(index.frames);
  if (fs::exists(dir / "joints.csv")) {
    parse_recording_joints(read_text_file(dir / "joints.csv"), (dir / "joints.csv").string(), recording.frames);
  }
  if (fs::exists(dir / "clouds.csv")) {
    parse_recording_clouds(read_text_file(dir / "clouds.csv"), (dir / "clouds.csv").string(), recording.frames);
  }
  for (size_t i = 0; i < index.rig_count; ++i) {
    const std::string rig_path = (dir / recording_rig_file(i)).string();
    auto rig = std::make_shared<Rig>(load_rig_yaml(rig_path));
    std::vector<std::string> names;
    for (const Camera& cam : rig->cameras()) names.push_back(cam.name);
    if (names != recording.camera_names) {
      throw ConfigError(rig_path + ": its cameras differ from those in recording.yaml");
    }
    recording.rigs.push_back(std::move(rig));
  }
  return recording;
}

std::vector<cv::Mat> Recording::load_images(const RecordingFrame& frame, std::vector<EncodedImage>* encoded) const {
  if (frame.rig_index >= rigs.size() || frame.image_files.size() != camera_names.size()) {
    throw std::runtime_error("recording '" + folder + "': frame " + std::to_string(frame.sequence) + " is malformed");
  }
  const Rig& rig = *rigs[frame.rig_index];
  std::vector<cv::Mat> images(frame.image_files.size());
  if (encoded) encoded->assign(images.size(), EncodedImage{});
  for (size_t i = 0; i < images.size(); ++i) {
    if (frame.image_files[i].empty()) continue;
    const std::string path = (fs::path(folder) / frame.image_files[i]).string();
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open image of camera '" + camera_names[i] + "'");
    // Sized from the file: these bytes live as long as the frame set, so no slack.
    in.seekg(0, std::ios::end);
    auto bytes = std::make_shared<std::vector<uint8_t>>(static_cast<size_t>(std::max<std::streamoff>(0, in.tellg())));
    in.seekg(0);
    in.read(reinterpret_cast<char*>(bytes->data()), static_cast<std::streamsize>(bytes->size()));
    if (!in) bytes->clear();  // unreadable: reported as corrupt below
    std::string why;
    cv::Mat image = bytes->empty() ? cv::Mat() : decode_image(*bytes, ImageColour::kAsStored, &why);
    // Decoded only in part (a file cut short) is corrupt too: never a grey patch replayed as picture.
    if (image.empty() || !why.empty()) {
      throw std::runtime_error(path + ": corrupt image of camera '" + camera_names[i] + "'" +
                               (why.empty() ? "" : " (" + why + ")"));
    }
    const Camera& cam = rig.cameras()[i];
    if (image.cols != cam.width || image.rows != cam.height) {
      throw std::runtime_error(path + ": image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                               ", camera '" + cam.name + "' is calibrated for " + std::to_string(cam.width) + "x" +
                               std::to_string(cam.height));
    }
    images[i] = std::move(image);
    if (encoded) (*encoded)[i] = {image_format_of(frame.image_files[i]), std::move(bytes)};
  }
  return images;
}

}  // namespace omniview
