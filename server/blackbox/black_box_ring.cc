#include "server/blackbox/black_box_ring.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <system_error>

namespace omniview {
namespace fs = std::filesystem;
using SystemClock = std::chrono::system_clock;

namespace {

// Below this, a failed write teaches the ring nothing about the disk (a vanished folder).
constexpr uint64_t kMinLearnedBudget = uint64_t{1} << 20;

std::string segment_name(SystemClock::time_point first) {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(first.time_since_epoch()).count();
  char name[32];
  std::snprintf(name, sizeof name, "%020lld", static_cast<long long>(ns));
  return name;
}

// The bytes a frame set will take at most: its images as they will be written (a source's
// JPEG as is; decoded pixels as PNG, which is smaller than raw), its cloud, and a block for
// each index file it may carry over a block boundary.
uint64_t expected_bytes(const FrameSet& frames) {
  uint64_t bytes = 3 * 4096;
  for (size_t i = 0; i < frames.images.size(); ++i) {
    const EncodedImage* encoded = i < frames.encoded.size() ? &frames.encoded[i] : nullptr;
    if (encoded && !encoded->format.empty() && encoded->bytes) {
      bytes += recording_disk_bytes(encoded->bytes->size());
    } else if (!frames.images[i].empty()) {
      bytes += recording_disk_bytes(frames.images[i].total() * frames.images[i].elemSize() + 1024);
    }
  }
  if (frames.cloud) bytes += recording_disk_bytes(frames.cloud->points.size() * 64 + 1024);  // every field of a point
  return bytes;
}

void remove_folder(const fs::path& folder, const std::function<void(const std::string&)>& log) {
  std::error_code ec;
  fs::remove_all(folder, ec);
  if (ec && log) log("cannot remove '" + folder.string() + "': " + ec.message());
}

}  // namespace

uint64_t folder_disk_bytes(const fs::path& folder) {
  std::error_code ec;
  uint64_t bytes = 4096;
  for (auto it = fs::recursive_directory_iterator(folder, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (it->is_directory(ec)) {
      bytes += 4096;
    } else if (it->is_regular_file(ec)) {
      bytes += recording_disk_bytes(it->file_size(ec));
    }
  }
  return bytes;
}

BlackBoxRing::BlackBoxRing(fs::path folder, std::string source, BlackBoxRingOptions options,
                           std::function<void(const std::string&)> log)
    : folder_(std::move(folder)), source_(std::move(source)), options_(options), log_(std::move(log)),
      budget_(options.max_bytes) {
  std::error_code ec;
  fs::create_directories(folder_, ec);
  if (ec) throw std::runtime_error("cannot create the black box folder '" + folder_.string() + "': " + ec.message());
  std::vector<fs::path> found;
  for (const auto& entry : fs::directory_iterator(folder_, ec)) {
    if (entry.is_directory()) found.push_back(entry.path());
  }
  if (ec) throw std::runtime_error("cannot read the black box folder '" + folder_.string() + "': " + ec.message());
  std::sort(found.begin(), found.end());  // by name: by time
  // Kept whatever their age: the minutes before a crash or a power cut are what a black box
  // is for. They go when newer frame sets push them out of the span (make_room).
  for (const auto& path : found) {
    try {
      const Recording recording = Recording::open(path.string());
      RingSegment segment{path, folder_disk_bytes(path), recording.frames.size(), recording.frames.front().capture_time,
                          recording.frames.back().capture_time};
      segments_.push_back(std::move(segment));
    } catch (const std::exception& e) {
      // Another version's segment, or one cut short before its first frame: not ours to
      // read, and in the way of the budget.
      if (log_) log_("dropped unreadable segment '" + path.string() + "': " + e.what());
      remove_folder(path, log_);
    }
  }
  // A budget made smaller since the last run.
  while (!segments_.empty() && bytes() > options_.max_bytes) drop_oldest();
  // Writable? Found now, at start, not at the first frame with a robot moving.
  const fs::path probe = folder_ / ".writable";
  if (FILE* f = std::fopen(probe.c_str(), "w")) {
    std::fclose(f);
    fs::remove(probe, ec);
  } else {
    throw std::runtime_error("cannot write in the black box folder '" + folder_.string() + "'");
  }
}

BlackBoxRing::~BlackBoxRing() {
  try {
    seal();
  } catch (...) {
  }
}

std::chrono::milliseconds BlackBoxRing::segment_length() const {
  using namespace std::chrono;
  return std::clamp(duration_cast<milliseconds>(options_.span / 10), milliseconds(2000), milliseconds(60000));
}

uint64_t BlackBoxRing::bytes() const {
  uint64_t sum = 0;
  for (const auto& s : segments_) sum += s.bytes;
  return sum;
}

size_t BlackBoxRing::frame_sets() const {
  size_t sum = 0;
  for (const auto& s : segments_) sum += s.frame_sets;
  return sum;
}

std::chrono::duration<double> BlackBoxRing::span() const {
  if (segments_.empty()) return std::chrono::duration<double>(0);
  return segments_.back().last - segments_.front().first;
}

void BlackBoxRing::drop_oldest() {
  if (writer_ && segments_.size() == 1) {
    seal();
    if (segments_.empty()) return;  // it held nothing complete: gone with the seal
  }
  remove_folder(segments_.front().folder, log_);
  segments_.pop_front();
}

void BlackBoxRing::make_room(uint64_t bytes, SystemClock::time_point now) {
  // Older than the span (a segment's worth of slack, so the span is always there)...
  const size_t open = writer_ ? 1 : 0;  // the segment being written stays
  while (segments_.size() > open && segments_.front().last < now - options_.span) drop_oldest();
  // ...and within the budget, the oldest first.
  while (!segments_.empty() && this->bytes() + bytes > budget_) drop_oldest();
}

void BlackBoxRing::start_segment(SystemClock::time_point first) {
  fs::path path = folder_ / segment_name(first);
  for (int i = 1; fs::exists(path); ++i) path = folder_ / (segment_name(first) + "_" + std::to_string(i));
  writer_ = std::make_unique<RecordingWriter>(path.string(), source_);
  segments_.push_back(RingSegment{path, 0, 0, first, first});
}

bool BlackBoxRing::write(const FrameSet& frames) {
  // A frame set with no image (a source's joints alone) shows nothing: not worth a line.
  const bool any_image = std::any_of(frames.images.begin(), frames.images.end(), [](const cv::Mat& m) { return !m.empty(); }) ||
                         std::any_of(frames.encoded.begin(), frames.encoded.end(), [](const EncodedImage& e) { return e.bytes != nullptr; });
  if (!any_image) return true;
  const uint64_t expected = expected_bytes(frames);
  if (expected > segment_bytes()) return false;
  if (writer_) {
    const RingSegment& open = segments_.back();
    if (open.bytes + expected > segment_bytes() || frames.capture_time - open.first >= segment_length() ||
        frames.capture_time < open.last) {  // a clock stepped back: its own segment
      seal();
    }
  }
  make_room(expected + (writer_ ? 0 : 3 * 4096), frames.capture_time);
  const bool fresh = !writer_;
  try {
    if (!writer_) start_segment(frames.capture_time);
    writer_->write(frames);
  } catch (...) {
    // The segment keeps what it wrote up to its last complete line; the next write starts
    // a new one. A disk with less room than max_bytes fills before the budget does: the
    // oldest segment goes now, so the ring keeps turning within the room there is.
    // A fresh segment that failed (its first files did not fit) is gone with the seal: the
    // oldest goes then even when it is the only one left, or a disk smaller than a segment
    // would keep its first seconds for good.
    try {
      // The disk is fuller than the budget said (other files, a small card): the ring
      // keeps to what it held, less a tenth, from now on, in segments an eighth of that.
      const uint64_t held = bytes();
      if (held >= kMinLearnedBudget && held * 9 / 10 < budget_) {
        budget_ = held * 9 / 10;
        if (log_) {
          log_("the disk filled at " + std::to_string(held >> 20) + " MiB, before max_bytes: the ring keeps to " +
               std::to_string(budget_ >> 20) + " MiB from now on");
        }
      }
      seal();
      if (segments_.size() > 1 || (fresh && !segments_.empty())) drop_oldest();
    } catch (...) {
    }
    throw;
  }
  RingSegment& open = segments_.back();
  open.bytes = writer_->disk_bytes();
  open.frame_sets = writer_->frames_written();
  open.last = frames.capture_time;
  return true;
}

void BlackBoxRing::seal() {
  if (!writer_) return;
  auto writer = std::move(writer_);
  RingSegment& open = segments_.back();
  std::exception_ptr failed;
  try {
    writer->close();
  } catch (...) {
    failed = std::current_exception();
  }
  std::error_code ec;
  if (open.frame_sets == 0 || !fs::exists(open.folder / "frames.csv", ec)) {  // nothing complete in it, or gone
    remove_folder(open.folder, log_);
    segments_.pop_back();
  } else {
    open.bytes = folder_disk_bytes(open.folder);
  }
  if (failed) std::rethrow_exception(failed);
}

std::vector<fs::path> BlackBoxRing::stage(const fs::path& staging) const {
  std::vector<fs::path> staged;
  const size_t closed = writer_ ? segments_.size() - 1 : segments_.size();
  for (size_t i = 0; i < closed; ++i) {
    const fs::path& from = segments_[i].folder;
    const fs::path to = staging / from.filename();
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(from, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
      const fs::path target = to / fs::relative(it->path(), from);
      if (it->is_directory()) {
        fs::create_directories(target);
      } else {
        fs::create_directories(target.parent_path());
        std::error_code link_error;
        fs::create_hard_link(it->path(), target, link_error);
        if (link_error) fs::copy_file(it->path(), target);  // a file system without hard links
      }
    }
    if (ec) throw std::runtime_error("cannot read black box segment '" + from.string() + "': " + ec.message());
    staged.push_back(to);
  }
  return staged;
}

}  // namespace omniview
