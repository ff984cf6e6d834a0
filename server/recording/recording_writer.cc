// RecordingWriter: writes a recording folder (layout in recording.h).
//
// Format, version 1:
//   recording.yaml  format: omniview-recording, version: 1, source: NAME,
//                   cameras: [names, rig order], created: ISO 8601 UTC
//   rig.yaml        the first rig (rig_to_yaml; masks beside it), rig_<n>.yaml later ones
//   frames.csv      header "sequence,capture_time_ns,rig,<camera>,...", then one line per
//                   frame set: sequence, capture time (ns since the Unix epoch), rig index,
//                   and per camera its image file relative to the folder (empty: absent)
//   images/         <frame number>_<camera index>.jpg|.png
//   joints.csv      optional, header "frame,joint,position", then per frame set that has
//                   joint positions one line per joint: frame number (0-based, the line of
//                   frames.csv after its header), joint name, position (rad or m); written
//                   before the frame's frames.csv line (older recordings have none)
//   clouds.csv      optional, header "frame,stamp_ns,file", then per frame set that carried
//                   a lidar cloud: frame number, the cloud's stamp (ns since the Unix epoch),
//                   clouds/<frame number>.pcd (binary PCD v0.7 with every field the cloud
//                   has, its frame and stamp in comments); written before the frame's line
//
// Each frame's images and rig are written before its frames.csv line, and the line is
// flushed at once: every complete line refers only to files already on disk.
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "core/cloud/cloud_file.h"
#include "core/io/image_codec.h"
#include "server/recording/recording.h"

namespace omniview {
namespace fs = std::filesystem;

namespace {
// Why a write failed, as the system said ("No space left on device"): errno of the
// failed call, which the stream leaves in place.
std::string os_reason() { return errno != 0 ? std::string(": ") + std::strerror(errno) : std::string(); }

}  // namespace

struct RecordingWriter::Impl {
  fs::path folder;
  std::string source_name;
  std::string created;
  std::mutex mutex;
  std::ofstream csv;
  std::ofstream joints_csv;  // opened with the first joints
  std::map<std::string, double> next_joints;
  std::ofstream clouds_csv;  // opened with the first cloud
  std::shared_ptr<const PointCloud> next_cloud;
  std::vector<std::string> camera_names;  // fixed by the first rig
  std::string last_rig_yaml;
  size_t rig_count = 0;
  size_t frames = 0;
  bool closed = false;
  uint64_t file_bytes = 0;  // images and clouds, each in whole blocks
  uint64_t top_bytes = 0;   // recording.yaml and the rigs (with any masks), in whole blocks

  void count_top_files();

  void start(const Rig& rig);
  size_t rig_index_for(const Rig& rig);
  void write_joints();
  void write_cloud();
};

void RecordingWriter::Impl::write_cloud() {
  const fs::path path = folder / "clouds.csv";
  if (!clouds_csv.is_open()) {
    fs::create_directories(folder / "clouds");
    clouds_csv.open(path, std::ios::binary | std::ios::trunc);
    clouds_csv << "frame,stamp_ns,file\n";
  }
  const std::string file = "clouds/" + std::to_string(frames) + ".pcd";
  const std::string pcd = format_pcd(*next_cloud, CloudEncoding::kBinary);
  std::ofstream out(folder / file, std::ios::binary | std::ios::trunc);
  out.write(pcd.data(), static_cast<std::streamsize>(pcd.size()));
  out.flush();
  if (!out) throw std::runtime_error("cannot write '" + (folder / file).string() + "'" + os_reason());
  file_bytes += recording_disk_bytes(pcd.size());
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(next_cloud->stamp.time_since_epoch()).count();
  clouds_csv << frames << ',' << ns << ',' << file << '\n';
  clouds_csv.flush();
  if (!clouds_csv) throw std::runtime_error("cannot append to '" + path.string() + "'" + os_reason());
  next_cloud.reset();
}

void RecordingWriter::set_next_cloud(std::shared_ptr<const PointCloud> cloud) {
  std::lock_guard lock(impl_->mutex);
  impl_->next_cloud = std::move(cloud);
}

void RecordingWriter::Impl::write_joints() {
  const fs::path path = folder / "joints.csv";
  if (!joints_csv.is_open()) {
    joints_csv.open(path, std::ios::binary | std::ios::trunc);
    joints_csv << "frame,joint,position\n";
  }
  joints_csv.precision(17);
  for (const auto& [name, position] : next_joints) {
    if (name.find_first_of(",\r\n") != std::string::npos) {
      throw std::invalid_argument("recording: joint name '" + name + "' cannot go in joints.csv (',' or newline)");
    }
    joints_csv << frames << ',' << name << ',' << position << '\n';
  }
  joints_csv.flush();
  if (!joints_csv) throw std::runtime_error("cannot append to '" + path.string() + "'" + os_reason());
  next_joints.clear();
}

void RecordingWriter::set_next_joints(std::map<std::string, double> joints) {
  std::lock_guard lock(impl_->mutex);
  impl_->next_joints = std::move(joints);
}

namespace {

std::string iso_utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

void write_file(const fs::path& path, const void* data, size_t size) {
  errno = 0;  // what a failure below leaves is its own reason
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.flush();
  if (!out) throw std::runtime_error("cannot write '" + path.string() + "'" + os_reason());
}

std::string extension_of(const std::string& format) {
  if (format == "jpeg") return ".jpg";
  if (format == "png") return ".png";
  throw std::invalid_argument("recording: unsupported image format '" + format + "' (jpeg or png)");
}

}  // namespace

RecordingWriter::RecordingWriter(const std::string& folder, const std::string& source_name)
    : impl_(std::make_unique<Impl>()) {
  impl_->folder = folder;
  impl_->source_name = source_name;
  impl_->created = iso_utc_now();
  std::error_code ec;
  if (fs::exists(impl_->folder, ec) && !fs::is_empty(impl_->folder, ec)) {
    throw std::runtime_error("recording folder '" + folder + "' exists and is not empty");
  }
  fs::create_directories(impl_->folder / "images", ec);
  if (ec) throw std::runtime_error("cannot create recording folder '" + folder + "': " + ec.message());
}

RecordingWriter::~RecordingWriter() {
  try {
    close();
  } catch (...) {
  }
}

// The first frame fixes the cameras: recording.yaml and the frames.csv header.
void RecordingWriter::Impl::start(const Rig& rig) {
  for (const Camera& cam : rig.cameras()) {
    if (cam.name.find_first_of(",\r\n") != std::string::npos) {
      throw std::invalid_argument("recording: camera name '" + cam.name + "' cannot go in frames.csv (',' or newline)");
    }
    camera_names.push_back(cam.name);
  }
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "format" << YAML::Value << "omniview-recording";
  out << YAML::Key << "version" << YAML::Value << 1;
  out << YAML::Key << "source" << YAML::Value << source_name;
  out << YAML::Key << "cameras" << YAML::Value << YAML::Flow << camera_names;
  out << YAML::Key << "created" << YAML::Value << created << YAML::EndMap;
  const std::string text = std::string(out.c_str()) + "\n";
  write_file(folder / "recording.yaml", text.data(), text.size());
  csv.open(folder / "frames.csv", std::ios::binary | std::ios::trunc);
  csv << "sequence,capture_time_ns,rig";
  for (const auto& name : camera_names) csv << ',' << name;
  csv << '\n';
  csv.flush();
  if (!csv) throw std::runtime_error("cannot write '" + (folder / "frames.csv").string() + "'" + os_reason());
}

size_t RecordingWriter::Impl::rig_index_for(const Rig& rig) {
  std::vector<std::string> names;
  for (const Camera& cam : rig.cameras()) names.push_back(cam.name);
  if (names != camera_names) {
    throw std::invalid_argument("recording: the rig's cameras changed; a recording keeps one camera set");
  }
  std::string text = rig_to_yaml(rig);
  if (rig_count > 0 && text == last_rig_yaml) return rig_count - 1;
  save_rig_yaml(rig, (folder / recording_rig_file(rig_count)).string());
  count_top_files();
  last_rig_yaml = std::move(text);
  return rig_count++;
}

void RecordingWriter::write(uint64_t sequence, std::chrono::system_clock::time_point capture_time, const Rig& rig,
                            const std::vector<RecordedImage>& images) {
  std::lock_guard lock(impl_->mutex);
  if (impl_->closed) throw std::logic_error("RecordingWriter::write after close");
  if (impl_->camera_names.empty()) impl_->start(rig);
  const size_t rig_index = impl_->rig_index_for(rig);
  std::vector<std::string> files(impl_->camera_names.size());
  for (const RecordedImage& image : images) {
    const auto it = std::find(impl_->camera_names.begin(), impl_->camera_names.end(), image.camera);
    if (it == impl_->camera_names.end()) {
      throw std::invalid_argument("recording: image for unknown camera '" + image.camera + "'");
    }
    const size_t cam = static_cast<size_t>(it - impl_->camera_names.begin());
    files[cam] = "images/" + std::to_string(impl_->frames) + "_" + std::to_string(cam) + extension_of(image.format);
    write_file(impl_->folder / files[cam], image.bytes.data(), image.bytes.size());
    impl_->file_bytes += recording_disk_bytes(image.bytes.size());
  }
  if (!impl_->next_joints.empty()) impl_->write_joints();
  if (impl_->next_cloud) impl_->write_cloud();
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(capture_time.time_since_epoch()).count();
  errno = 0;
  impl_->csv << sequence << ',' << ns << ',' << rig_index;
  for (const auto& file : files) impl_->csv << ',' << file;
  impl_->csv << '\n';
  impl_->csv.flush();
  if (!impl_->csv) throw std::runtime_error("cannot append to '" + (impl_->folder / "frames.csv").string() + "'" + os_reason());
  ++impl_->frames;
}

void RecordingWriter::write(const FrameSet& frames) {
  if (!frames.rig) throw std::invalid_argument("recording: frame set without a rig");
  const auto& cameras = frames.rig->cameras();
  if (frames.images.size() != cameras.size()) {
    throw std::invalid_argument("recording: frame set has " + std::to_string(frames.images.size()) +
                                " images for " + std::to_string(cameras.size()) + " cameras");
  }
  std::vector<RecordedImage> images;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const cv::Mat& mat = frames.images[i];
    const EncodedImage* encoded = i < frames.encoded.size() ? &frames.encoded[i] : nullptr;
    const bool has_bytes = encoded && !encoded->format.empty() && encoded->bytes;
    if (mat.empty() && !has_bytes) continue;
    // Bytes kept as received are the camera's whole image, whatever size the source decoded
    // them to for its views (a JPEG's DCT scaling): only pixels to encode must match.
    if (!has_bytes && (mat.cols != cameras[i].width || mat.rows != cameras[i].height)) {
      throw std::invalid_argument("recording: camera '" + cameras[i].name + "' image is " + std::to_string(mat.cols) +
                                  "x" + std::to_string(mat.rows) + ", its calibration is " +
                                  std::to_string(cameras[i].width) + "x" + std::to_string(cameras[i].height));
    }
    RecordedImage image{cameras[i].name, "png", {}};
    if (has_bytes) {
      image.format = encoded->format;
      image.bytes = *encoded->bytes;
    } else {
      try {
        image.bytes = encode_png(mat);
      } catch (const std::exception& e) {
        throw std::runtime_error("recording: camera '" + cameras[i].name + "': " + e.what());
      }
    }
    images.push_back(std::move(image));
  }
  if (frames.joints) set_next_joints(*frames.joints);
  if (frames.cloud) set_next_cloud(frames.cloud);
  write(frames.sequence, frames.capture_time, *frames.rig, images);
}

size_t RecordingWriter::frames_written() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->frames;
}

// The few files beside the index (a rig's masks are written by save_rig_yaml): stat'ed
// when a rig is written, not counted one by one.
void RecordingWriter::Impl::count_top_files() {
  top_bytes = 0;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    const bool index = name.size() > 4 && name.substr(name.size() - 4) == ".csv";  // counted as they grow
    if (!entry.is_regular_file(ec) || index) continue;
    top_bytes += recording_disk_bytes(entry.file_size(ec));
  }
}

uint64_t RecordingWriter::disk_bytes() const {
  std::lock_guard lock(impl_->mutex);
  const Impl& i = *impl_;
  uint64_t bytes = i.file_bytes + i.top_bytes;
  uint64_t folders = 2;  // the recording's and images/
  // The index files as far as written (tellp: appended so far; closed ones count nothing
  // more, their last size was counted when they were open).
  for (const std::ofstream* csv : {&i.csv, &i.joints_csv, &i.clouds_csv}) {
    if (!csv->is_open()) continue;
    const auto at = const_cast<std::ofstream*>(csv)->tellp();
    if (at > 0) bytes += recording_disk_bytes(static_cast<uint64_t>(at));
  }
  if (i.clouds_csv.is_open()) ++folders;  // clouds/
  return bytes + folders * 4096;
}

void RecordingWriter::close() {
  std::lock_guard lock(impl_->mutex);
  if (impl_->closed) return;
  impl_->closed = true;
  if (impl_->joints_csv.is_open()) impl_->joints_csv.close();
  if (impl_->clouds_csv.is_open()) impl_->clouds_csv.close();
  if (impl_->csv.is_open()) {
    impl_->csv.close();
    if (impl_->csv.fail()) throw std::runtime_error("cannot close '" + (impl_->folder / "frames.csv").string() + "'");
  }
}

}  // namespace omniview
