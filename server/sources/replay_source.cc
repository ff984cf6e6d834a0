#include "server/sources/replay_source.h"

#include <filesystem>

#include "server/sources/source_config_helpers.h"

namespace omniview {

using Clock = std::chrono::steady_clock;

ReplaySource::ReplaySource(const SourceConfig& config) : Source(config.name) {
  const YamlReader& r = *config.reader;
  r.expect_keys(config.node, config.path, {"name", "type", "recording", "rate_hz", "speed", "loop"});
  const std::string folder = config_path(config, "recording");
  try {
    recording_ = Recording::open(folder);
  } catch (const std::exception& e) {
    std::string why = e.what();
    // The rule for relative paths, said where people trip over it: `omniview record -o
    // recordings/lab` wrote into the CLI's working directory, not the config's folder.
    if (std::filesystem::path(r.text(config.node["recording"], config.path + ".recording")).is_relative()) {
      why += " (a relative path in a config resolves against the config file's folder, " +
             (config.folder.empty() ? std::string(".") : config.folder) + ")";
    }
    r.fail(config.node["recording"], config.path + ".recording", why);
  }
  rate_hz_ = positive_number(config, "rate_hz", 0);
  speed_ = positive_number(config, "speed", 1);
  if (config.node["loop"]) loop_ = r.boolean(config.node["loop"], config.path + ".loop");
  current_rig_ = recording_.rigs.at(recording_.frames.front().rig_index);
  has_clouds_ = recording_.has_clouds();

  const size_t count = recording_.frames.size();
  std::chrono::duration<double> period(rate_hz_ > 0 ? 1.0 / rate_hz_ : 0.1);
  if (rate_hz_ == 0 && count > 1) {
    const std::chrono::duration<double> span =
        recording_.frames.back().capture_time - recording_.frames.front().capture_time;
    // The gap from the last frame back to the first: the recording's mean frame interval.
    if (span.count() > 0) period = span / double(count - 1);
  }
  const std::chrono::duration<double> loop_seconds = offset_of(count - 1) + period / speed_;
  loop_length_ = std::chrono::duration_cast<Clock::duration>(loop_seconds);
}

ReplaySource::~ReplaySource() { stop(); }

std::shared_ptr<const Rig> ReplaySource::rig() const {
  std::lock_guard lock(mutex_);
  return current_rig_;
}

void ReplaySource::start(FrameCallback on_frame) {
  {
    std::lock_guard lock(mutex_);
    health_.connected = true;
  }
  thread_.start([this, on_frame = std::move(on_frame)] { run(on_frame); });
}

void ReplaySource::stop() {
  thread_.stop();
  std::lock_guard lock(mutex_);
  health_.connected = false;
}

SourceHealth ReplaySource::health() const {
  std::lock_guard lock(mutex_);
  return health_;
}

Clock::duration ReplaySource::offset_of(size_t index) const {
  std::chrono::duration<double> seconds(0);
  if (rate_hz_ > 0) {
    seconds = std::chrono::duration<double>(double(index) / rate_hz_);
  } else {
    seconds = recording_.frames[index].capture_time - recording_.frames.front().capture_time;
  }
  return std::chrono::duration_cast<Clock::duration>(seconds / speed_);
}

ReplaySource::Decoded ReplaySource::decode(size_t index) {
  Decoded decoded;
  try {
    // The files' bytes go along: a recording of this replay stores them unchanged.
    decoded.images = recording_.load_images(recording_.frames[index], &decoded.encoded);
    if (cloud_wanted_) decoded.cloud = recording_.load_cloud(recording_.frames[index]);
  } catch (const std::exception& e) {
    std::lock_guard lock(mutex_);
    ++health_.errors;
    health_.message = std::string("skipped a frame: ") + e.what();
    return {};
  }
  return decoded;
}

void ReplaySource::run(FrameCallback on_frame) {
  Clock::time_point loop_start = Clock::now();
  uint64_t sequence = 0;
  uint64_t rig_version = 0;
  std::shared_ptr<const Rig> last_rig;
  size_t index = 0;
  // Decoded before its deadline, so decoding time does not delay delivery.
  Decoded next = decode(index);
  for (;;) {
    if (!thread_.wait_until(loop_start + offset_of(index))) return;
    if (!next.images.empty()) {
      auto frames = std::make_shared<FrameSet>();
      const auto& rig = recording_.rigs[recording_.frames[index].rig_index];
      // A new version whenever the rig differs from the last delivered, looping back included.
      if (rig != last_rig) {
        last_rig = rig;
        ++rig_version;
        std::lock_guard lock(mutex_);
        current_rig_ = rig;
      }
      frames->sequence = ++sequence;
      frames->capture_time = std::chrono::system_clock::now();
      frames->arrival = Clock::now();
      frames->rig = rig;
      frames->rig_version = rig_version;
      frames->images = std::move(next.images);
      frames->encoded = std::move(next.encoded);
      frames->joints = recording_.frames[index].joints;  // the legs as they were, for the overlay
      if (next.cloud) {
        next.cloud->stamp = frames->capture_time + (next.cloud->stamp - recording_.frames[index].capture_time);
        frames->cloud = std::move(next.cloud);
      }
      on_frame(std::move(frames));
      std::lock_guard lock(mutex_);
      ++health_.frames;
    }
    if (++index == recording_.frames.size()) {
      if (!loop_) {
        std::lock_guard lock(mutex_);
        health_.connected = false;
        if (health_.message.empty()) health_.message = "end of recording (loop: false)";
        return;
      }
      index = 0;
      loop_start += loop_length_;
      // After a stall, start the next loop now instead of racing through it.
      if (loop_start + loop_length_ < Clock::now()) loop_start = Clock::now();
    }
    next = decode(index);
  }
}

std::unique_ptr<Source> make_replay_source(const SourceConfig& config) {
  return std::make_unique<ReplaySource>(config);
}

}  // namespace omniview
