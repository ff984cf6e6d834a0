#include "server/blackbox/snapshot_merge.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>

#include "server/blackbox/black_box_ring.h"
#include "server/recording/recording.h"

namespace omniview {
namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read '" + path.string() + "'");
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string format_of(const fs::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".jpg" || ext == ".jpeg") return "jpeg";
  if (ext == ".png") return "png";
  throw std::runtime_error("'" + file.string() + "': not an image the recording format keeps (.jpg or .png)");
}

}  // namespace

SnapshotSummary merge_segments(const std::vector<fs::path>& segments, const fs::path& out, const std::string& source) {
  SnapshotSummary summary;
  summary.source = source;
  summary.folder = out;
  std::vector<Recording> readable;
  for (const auto& folder : segments) {
    try {
      readable.push_back(Recording::open(folder.string()));
    } catch (const std::exception& e) {
      summary.note += std::string(summary.note.empty() ? "" : "; ") + "left out " + folder.filename().string() + ": " +
                      e.what();
    }
  }
  if (readable.empty()) throw std::runtime_error("no frame sets to save");
  // One recording keeps one camera set: the newest segments that share the newest's.
  size_t first = readable.size() - 1;
  while (first > 0 && readable[first - 1].camera_names == readable.back().camera_names) --first;
  if (first > 0) {
    summary.note += std::string(summary.note.empty() ? "" : "; ") + "the source's cameras changed: kept the " +
                    std::to_string(readable.size() - first) + " newest of " + std::to_string(readable.size()) +
                    " segments";
  }
  RecordingWriter writer(out.string(), source);
  std::optional<std::chrono::system_clock::time_point> oldest, newest;
  uint64_t sequence = 0;  // a source's count starts again with the daemon: kept increasing
  for (size_t s = first; s < readable.size(); ++s) {
    const Recording& recording = readable[s];
    for (const RecordingFrame& frame : recording.frames) {
      std::vector<RecordedImage> images;
      for (size_t cam = 0; cam < frame.image_files.size(); ++cam) {
        if (frame.image_files[cam].empty()) continue;
        const fs::path file = fs::path(recording.folder) / frame.image_files[cam];
        images.push_back(RecordedImage{recording.camera_names[cam], format_of(file), read_bytes(file)});
      }
      if (frame.joints) writer.set_next_joints(*frame.joints);
      if (!frame.cloud_file.empty()) writer.set_next_cloud(recording.load_cloud(frame));
      sequence = std::max(sequence + 1, frame.sequence);
      writer.write(sequence, frame.capture_time, *recording.rigs.at(frame.rig_index), images);
      if (!oldest) oldest = frame.capture_time;
      newest = frame.capture_time;
    }
  }
  writer.close();
  summary.frame_sets = writer.frames_written();
  if (oldest) summary.span = *newest - *oldest;
  summary.bytes = folder_disk_bytes(out);
  return summary;
}

}  // namespace omniview
