// A recording: what a source delivered (images, capture times, the rig), on disk, so the
// `replay` source can play it back. `omniview record` writes one from a running daemon.
//
// Layout of a recording folder (format described fully in recording.cc):
//   recording.yaml   format name and version, source name, camera names, created time
//   rig.yaml         the rig in our rig YAML schema (re-written as rig_<n>.yaml if it changes)
//   frames.csv       one line per frame set, appended as it is written, so a recording cut
//                    short (killed, disk full) stays readable up to its last complete line
//   images/          one file per camera image, as delivered (JPEG bytes kept) or PNG
//   joints.csv       optional: the robot's joint positions the source reported with each
//                    frame set (for the robot overlay of a replay)
//   clouds.csv       optional: which frame sets carried a lidar cloud, its stamp and file
//   clouds/          one binary PCD per cloud (points, frame, stamp and every per-point field)
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "core/rig/rig.h"
#include "server/source/frame_set.h"

namespace omniview {

// One camera image as stored: its encoded bytes and format ("jpeg" or "png").
struct RecordedImage {
  std::string camera;
  std::string format;
  std::vector<uint8_t> bytes;
};

class RecordingWriter {
 public:
  // Creates `folder` (it must not exist or be empty). Throws std::runtime_error naming the
  // path on failure.
  RecordingWriter(const std::string& folder, const std::string& source_name);
  ~RecordingWriter();

  // Writes the rig (when it differs from the last one written) and one frame set. Images
  // are stored as given (encoded bytes); a camera missing from `images` is recorded as
  // absent for that frame.
  void write(uint64_t sequence, std::chrono::system_clock::time_point capture_time, const Rig& rig,
             const std::vector<RecordedImage>& images);
  // Convenience for a FrameSet: keeps the source's encoded bytes, PNG-encodes the rest.
  void write(const FrameSet& frames);
  // The joint positions (name -> rad, or m) that go with the next write(): written to
  // joints.csv before that frame set's frames.csv line.
  void set_next_joints(std::map<std::string, double> joints);
  // The lidar cloud that goes with the next write(): stored as clouds/<frame>.pcd and
  // indexed in clouds.csv before that frame set's frames.csv line.
  void set_next_cloud(std::shared_ptr<const PointCloud> cloud);

  size_t frames_written() const;
  // What the folder takes on disk so far: every file and folder in whole 4 KiB blocks
  // (recording_disk_bytes), so a budget on it holds on any usual file system.
  uint64_t disk_bytes() const;
  void close();  // flushes; also done by the destructor

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct RecordingFrame {
  uint64_t sequence = 0;
  std::chrono::system_clock::time_point capture_time;
  size_t rig_index = 0;                 // into Recording::rigs
  std::vector<std::string> image_files;  // per camera (rig order); empty: absent
  // The robot's joint positions as recorded with this frame set; null: none recorded.
  std::shared_ptr<const std::map<std::string, double>> joints;
  // The lidar cloud recorded with this frame set (relative path; empty: none) and its stamp.
  std::string cloud_file;
  std::chrono::system_clock::time_point cloud_stamp;
};

// Reads the index (not the images). Throws ConfigError naming the file and line for a
// missing or malformed recording.
struct Recording {
  std::string folder;
  std::string source_name;
  std::vector<std::string> camera_names;
  std::vector<std::shared_ptr<const Rig>> rigs;
  std::vector<RecordingFrame> frames;  // in capture order, at least one

  static Recording open(const std::string& folder);
  // Decodes one frame's images (CV_8UC1 or CV_8UC3 BGR, rig order). Throws
  // std::runtime_error naming the file for a missing or corrupt image, or one whose size
  // differs from its camera's calibration. With `encoded`, also hands back each file's
  // bytes (rig order), so a recording of a replay keeps them as they are.
  std::vector<cv::Mat> load_images(const RecordingFrame& frame, std::vector<EncodedImage>* encoded = nullptr) const;
  // Reads one frame's cloud (null when it has none). Throws std::runtime_error naming the
  // file for a missing or malformed one.
  std::shared_ptr<PointCloud> load_cloud(const RecordingFrame& frame) const;
  bool has_clouds() const;
};

// The index of a recording (recording.yaml + frames.csv) as parsed, before any rig or
// image is read: what Recording::open builds on, and what the fuzz target exercises.
struct RecordingIndex {
  std::string source_name;
  std::vector<std::string> camera_names;
  size_t rig_count = 0;  // rigs the frames refer to: recording_rig_file(0 .. rig_count-1)
  std::vector<RecordingFrame> frames;
};

// Parses the two index files' text; `folder` only names them in messages. Throws
// ConfigError naming file and line. A last line without its newline (a recording cut
// short) is ignored.
RecordingIndex parse_recording_index(const std::string& recording_yaml, const std::string& frames_csv,
                                     const std::string& folder);

// Adds joints.csv's positions (header "frame,joint,position", then one line per frame
// index, joint and position) to `frames`; `file` names it in messages. Throws ConfigError
// naming file and line. A last line without its newline is ignored.
void parse_recording_joints(const std::string& joints_csv, const std::string& file,
                            std::vector<RecordingFrame>& frames);

// Adds clouds.csv's entries (header "frame,stamp_ns,file", then one line per frame that
// has a cloud: frame index, the cloud's stamp in ns since the Unix epoch, its PCD file
// relative to the folder) to `frames`; `file` names it in messages. Throws ConfigError
// naming file and line. A last line without its newline is ignored.
void parse_recording_clouds(const std::string& clouds_csv, const std::string& file,
                            std::vector<RecordingFrame>& frames);

// Bytes a file of `size` bytes takes on disk, counted in whole 4 KiB blocks (ext4's and
// most file systems' block): a recording of many small images takes more than their sum.
inline uint64_t recording_disk_bytes(uint64_t size) { return (size + 4095) / 4096 * 4096; }

// "rig.yaml" for the first rig, "rig_<n>.yaml" for later ones.
std::string recording_rig_file(size_t index);

}  // namespace omniview
